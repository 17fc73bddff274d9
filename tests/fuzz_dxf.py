"""Mutation fuzzer for camcad's readers: damaged DXF and table files must end in a result or one clear line.

Each case mutates a sample file (bytes flipped, truncated, group codes shuffled, numbers replaced by
garbage, lines dropped or duplicated, huge vertex counts), runs ``camcad check --json`` on it in this
process (a 120 s wall-clock alarm interrupts a hang; the case may use 10 s of CPU), and classifies the outcome:
- ok:        exit 0 or 1 and one JSON object on stdout;
- error:     exit 2 and exactly one line "camcad: error: ..." on stderr, not an internal error;
- FINDING:   anything else (a traceback, an internal error, several lines, a hang, more than 10 s of CPU, a
             changed input).

Long run:  python tests/fuzz_dxf.py --cases 2000 --seed 1
The test suite runs a short, fixed-seed run (tests/io/test_fuzz.py).
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import io
import json
import random
import resource
import signal
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CORPUS = sorted((ROOT / "samples" / "dxf").glob("*.dxf")) + [ROOT / "samples" / "law_table.csv"]
TIME_LIMIT_S = 10      # CPU seconds a case may use (CPU, not wall time: the machine may be shared)
HANG_S = 120           # wall seconds after which a case is a hang (generous, for a loaded machine)


@dataclass(frozen=True)
class Outcome:
    case: int
    seed_file: str
    mutation: str
    status: str         # "ok", "error" or "FINDING"
    detail: str
    seconds: float      # wall time
    cpu: float = 0.0    # CPU seconds of the case (this process: user + system)


class _Timeout(Exception):
    pass


def _alarm(signum, frame):  # noqa: ARG001
    raise _Timeout()


def mutate(data: bytes, rng: random.Random) -> tuple[bytes, str]:
    """One random mutation of a file's bytes, and its name."""
    kind = rng.choice(["flip", "truncate", "shuffle_codes", "garbage_number", "drop_lines", "duplicate_lines",
                       "huge_count", "many_vertices", "swap_sections"])
    lines = data.split(b"\n")
    if kind == "flip":
        buf = bytearray(data)
        for _ in range(rng.randint(1, 20)):
            if buf:
                buf[rng.randrange(len(buf))] = rng.randrange(256)
        return bytes(buf), kind
    if kind == "truncate":
        return data[: rng.randrange(max(1, len(data)))], kind
    if kind == "shuffle_codes":
        # swap the group codes of a few tag pairs (even lines are codes in an ASCII DXF)
        codes = list(range(0, len(lines) - 1, 2))
        for _ in range(rng.randint(1, 10)):
            i, j = rng.choice(codes), rng.choice(codes)
            lines[i], lines[j] = lines[j], lines[i]
        return b"\n".join(lines), kind
    if kind == "garbage_number":
        for _ in range(rng.randint(1, 5)):
            i = rng.randrange(len(lines))
            lines[i] = rng.choice([b"nan", b"inf", b"-inf", b"1e308", b"-1e308", b"1e-320", b"x", b"", b"0x1F",
                                   b"9" * 400])
        return b"\n".join(lines), kind
    if kind == "drop_lines":
        start = rng.randrange(len(lines))
        del lines[start: start + rng.randint(1, 7)]
        return b"\n".join(lines), kind
    if kind == "duplicate_lines":
        start = rng.randrange(len(lines))
        chunk = lines[start: start + rng.randint(1, 12)]
        lines[start:start] = chunk * rng.randint(1, 50)
        return b"\n".join(lines), kind
    if kind == "huge_count":
        for i in range(0, len(lines) - 1):
            if lines[i].strip() in (b"90", b"73", b"74", b"72"):
                lines[i + 1] = str(rng.choice([10**9, 2**31 - 1, -1, 0])).encode()
        return b"\n".join(lines), kind
    if kind == "many_vertices":
        # repeat one vertex pair (10/20) many times: a polyline of 100k+ vertices, most of them equal
        for i in range(0, len(lines) - 3):
            if lines[i].strip() == b"10" and lines[i + 2].strip() == b"20":
                lines[i:i] = lines[i: i + 4] * rng.randint(10_000, 60_000)
                break
        return b"\n".join(lines), kind
    sections = data.split(b"SECTION")
    rng.shuffle(sections)
    return b"SECTION".join(sections), "swap_sections"


def run_case(case: int, seed_file: Path, data: bytes, mutation: str, workdir: Path) -> Outcome:
    from camcad.cli import main

    suffix = seed_file.suffix
    path = workdir / f"case{case}{suffix}"
    path.write_bytes(data)
    digest = hashlib.sha256(data).hexdigest()
    out, err = io.StringIO(), io.StringIO()
    code = None
    start = time.perf_counter()
    cpu_start = _cpu()
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(HANG_S)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                main(["check", str(path), "--json"])
                code = 0
            except SystemExit as stop:
                code = int(stop.code or 0)
    except _Timeout:
        code = None
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    seconds = time.perf_counter() - start
    cpu = _cpu() - cpu_start
    changed = hashlib.sha256(path.read_bytes()).hexdigest() != digest
    path.unlink()
    status, detail = classify(code, out.getvalue(), err.getvalue(), changed, cpu)
    return Outcome(case, seed_file.name, mutation, status, detail, seconds, cpu)


def _cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def classify(code, stdout: str, stderr: str, changed: bool, cpu: float = 0.0) -> tuple[str, str]:
    if changed:
        return "FINDING", "the input file was changed"
    if code is None:
        return "FINDING", f"still running after {HANG_S} s"
    if cpu > TIME_LIMIT_S:
        return "FINDING", f"{cpu:.1f} s of CPU, past {TIME_LIMIT_S} s"
    lines = stderr.strip().splitlines()
    if code in (0, 1):
        try:
            json.loads(stdout)
        except ValueError:
            return "FINDING", f"exit {code} without one JSON object on stdout"
        return "ok", f"exit {code}"
    if code == 2 and len(lines) == 1 and lines[0].startswith("camcad: error: ") \
            and "internal error" not in lines[0] and "Traceback" not in stderr:
        return "error", lines[0][:200]
    return "FINDING", f"exit {code}: {stderr.strip()[:300]}"


def fuzz(cases: int, seed: int) -> list[Outcome]:
    rng = random.Random(seed)
    outcomes = []
    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(tmp)
        for case in range(cases):
            seed_file = rng.choice(CORPUS)
            data, mutation = mutate(seed_file.read_bytes(), rng)
            outcomes.append(run_case(case, seed_file, data, mutation, workdir))
    return outcomes


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=200)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    start = time.perf_counter()
    outcomes = fuzz(args.cases, args.seed)
    findings = [o for o in outcomes if o.status == "FINDING"]
    counts = {s: sum(o.status == s for o in outcomes) for s in ("ok", "error", "FINDING")}
    slowest = max(outcomes, key=lambda o: o.cpu)
    print(f"{len(outcomes)} cases (seed {args.seed}) in {time.perf_counter() - start:.1f} s: "
          f"{counts['ok']} results, {counts['error']} clear errors, {counts['FINDING']} findings; "
          f"slowest case {slowest.cpu:.2f} s of CPU ({slowest.mutation} of {slowest.seed_file})")
    for finding in findings:
        print(f"FINDING case {finding.case}: {finding.mutation} of {finding.seed_file}: {finding.detail}")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    sys.exit(main())
