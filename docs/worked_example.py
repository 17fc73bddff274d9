"""Run the README's worked example exactly as written, and compare what each command prints.

The README holds the example between ``<!-- worked-example -->`` and ``<!-- /worked-example -->``: each
```sh block is one command, run in a fresh folder that holds a copy of the sample it names; the ```text
block after it is what the command prints (stdout, then stderr), a line ``...`` standing for any number of
lines. tests/project/test_readme_example.py runs it; ``python docs/worked_example.py`` runs it too and refreshes
the example's pictures in docs/img/ (the fix plot, the summary plot and LibreCAD's render of the
profile), so that every figure and picture in that section comes from these commands.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
START, END = "<!-- worked-example -->", "<!-- /worked-example -->"
IMAGES = {"press_feed.fixed.png": "worked-fix.png", "press_feed/summary.png": "worked-summary.png"}


@dataclass
class Step:
    command: str
    expected: list[str]
    code: int

    def environment(self) -> dict[str, str]:
        """The ``NAME=value`` assignments before the program (``QT_QPA_PLATFORM=offscreen librecad ...``)."""
        return dict(word.split("=", 1) for word in _assignments(shlex.split(self.command)))

    def words(self) -> list[str]:
        """The program and its arguments, without the leading ``NAME=value`` assignments."""
        words = shlex.split(self.command)
        return words[len(_assignments(words)):]


def _assignments(words: list[str]) -> list[str]:
    out = []
    for word in words:
        if not re.fullmatch(r"[A-Z_][A-Z0-9_]*=\S*", word):
            break
        out.append(word)
    return out


def steps(readme: Path = ROOT / "README.md") -> list[Step]:
    """The commands of the worked example with what they print and their exit code (``# exit N``)."""
    text = readme.read_text(encoding="utf-8")
    section = text[text.index(START) + len(START):text.index(END)]
    blocks = re.findall(r"```(sh|text)\n(.*?)```", section, flags=re.S)
    found = []
    for (kind, body), (next_kind, next_body) in zip(blocks, blocks[1:] + [("", "")]):
        if kind != "sh":
            continue
        lines = [line for line in body.strip().splitlines() if line.strip()]
        command = lines[0]
        code = int(re.search(r"# exit (\d)", body).group(1)) if "# exit" in body else 0
        command = command.split("  #")[0].strip()
        found.append(Step(command, next_body.rstrip("\n").splitlines() if next_kind == "text" else [], code))
    return found


def matches(expected: list[str], actual: list[str]) -> bool:
    """``actual`` equals ``expected`` line for line (trailing blanks ignored), ``...`` matching any lines."""
    pattern = "\n".join(".*?" if line.strip() == "..." else _literal(line.rstrip()) for line in expected)
    return re.fullmatch(pattern, "\n".join(line.rstrip() for line in actual), flags=re.S) is not None


#: a figure at round-off level (|x| < 1e-12, printed as e.g. -8.632e-15): its digits depend on the BLAS and
#: the platform, so any other round-off figure matches it
_ROUND_OFF = r"-?\d\.\d{3}e-(?:1[3-9]|[2-9]\d|\d{3})"


def _literal(line: str) -> str:
    parts = re.split(_ROUND_OFF, line)
    return (r"\s*" + _ROUND_OFF).join(re.escape(p.rstrip(" ") if i < len(parts) - 1 else p)
                                      for i, p in enumerate(parts))


def run(folder: Path, camcad: str = "camcad",
        skip: tuple[str, ...] = ()) -> list[tuple[Step, subprocess.CompletedProcess]]:
    """Run every step in ``folder`` (the samples it names copied in), except those whose program is in
    ``skip``; return each step and its result."""
    found = steps()
    for step in found:
        for word in shlex.split(step.command):
            if word.startswith("samples/"):
                (folder / word).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(ROOT / word, folder / word)
    env = {**os.environ, "COLUMNS": "200", "QT_QPA_PLATFORM": "offscreen"}
    out = []
    for step in found:
        words = step.words()
        if words[0] in skip:
            continue
        if words[0] == "camcad":
            words[0] = camcad
        done = subprocess.run(words, cwd=folder, capture_output=True, text=True, env={**env, **step.environment()},
                              timeout=300)
        out.append((step, done))
    return out


def main() -> int:
    camcad = str(Path(sys.executable).parent / "camcad")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        failed = 0
        for step, done in run(folder, camcad):
            printed = (done.stdout + done.stderr).rstrip("\n").splitlines()
            ok = done.returncode == step.code and matches(step.expected, printed)
            failed += not ok
            print(f"{'ok  ' if ok else 'DIFF'} exit {done.returncode}  {step.command}")
            if not ok:
                print("\n".join(printed))
        for source, target in IMAGES.items():
            shutil.copy2(folder / source, ROOT / "docs" / "img" / target)
        pdf = folder / "press_feed" / "profile.pdf"
        if pdf.exists():
            subprocess.run(["pdftoppm", "-png", "-r", "60", "-singlefile", str(pdf),
                            str(ROOT / "docs" / "img" / "worked-librecad")], check=True, timeout=60)
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
