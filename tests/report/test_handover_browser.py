"""The design handed over (issue 32), opened as a reader opens it: `camcad profile --animate --report` on the
default cam, then animation.html and report.html in Debian's headless Chromium driven by Playwright.

- the animation loads, plays (the frame advances and the cam turns), has 360 frames at the default 1 deg step,
  and the browser reports no console error;
- every check row of report.html (``tr[data-check]``) is a check of report.json, with the same value, limit and
  margin, and every check of report.json has its row;
- the report reads on a phone (no sideways scrolling of the page) and prints to PDF through Chromium.

Required in CI (CAMCAD_REQUIRE_BROWSER=1: a missing browser fails); skipped locally without Chromium.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest

REQUIRED = os.environ.get("CAMCAD_REQUIRE_BROWSER") == "1"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def _chromium() -> str:
    for candidate in (os.environ.get("CAMCAD_CHROMIUM"), shutil.which("chromium-headless-shell"),
                      shutil.which("chromium"), shutil.which("chromium-browser")):
        if candidate and Path(candidate).exists():
            return candidate
    if REQUIRED:
        pytest.fail("CAMCAD_REQUIRE_BROWSER=1 but no Chromium found")
    pytest.skip("no Chromium found (apt-get install chromium-headless-shell or chromium)")


@pytest.fixture(scope="module")
def browser():
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        if REQUIRED:
            pytest.fail("CAMCAD_REQUIRE_BROWSER=1 but the playwright package is not installed")
        pytest.skip("the playwright package is not installed")
    executable = _chromium()
    with sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=executable, args=ARGS)
        try:
            yield chromium
        finally:
            chromium.close()


def _page(browser, url: str, width: int = 1280, height: int = 900):
    page = browser.new_page(viewport={"width": width, "height": height})
    errors: list[str] = []
    page.on("console", lambda message: errors.append(message.text) if message.type == "error" else None)
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.on("requestfailed", lambda request: errors.append(f"request failed: {request.url}"))
    page.goto(url)
    return page, errors


def _checks_of(report: dict) -> dict[str, dict]:
    """Every check of report.json by its path: an object with value, limit and margin under a "checks" object."""
    found = {}
    stack = [([], report)]
    while stack:
        path, node = stack.pop()
        if isinstance(node, dict):
            for key, value in node.items():
                if path and path[-1] == "checks" and isinstance(value, dict) and {"value", "limit", "margin"} <= set(
                        value):
                    found[json.dumps([*path, key])] = value
                else:
                    stack.append(([*path, key], value))
        elif isinstance(node, list):
            stack.extend(([*path, str(k)], item) for k, item in enumerate(node))
    return found


@pytest.fixture(scope="module")
def handed_over(tmp_path_factory):
    from camcad.cli import main

    folder = tmp_path_factory.mktemp("handover") / "default"
    try:
        main(["profile", "--animate", "--report", "-o", str(folder)])
    except SystemExit as stop:
        assert int(stop.code or 0) == 0
    return folder


def test_the_default_cam_writes_the_animation_and_the_report(handed_over):
    for name in ("animation.html", "report.html", "report.json", "summary.png", "profile.dxf"):
        assert (handed_over / name).is_file(), name
    report = json.loads((handed_over / "report.json").read_text())
    assert str(handed_over / "report.html") in report["outputs"]
    assert report["animation"]["frames"] == 360


def test_the_animation_plays_its_360_frames_without_a_console_error(browser, handed_over):
    page, errors = _page(browser, (handed_over / "animation.html").as_uri())
    try:
        page.wait_for_function("window.camcadAnimation && window.camcadAnimation.shown > 20", timeout=20000)
        assert page.get_attribute("#camcad-mechanism", "data-frames") == "360"
        assert page.evaluate("window.camcadAnimation.frames") == 360
        assert page.get_attribute("#camcad-slider", "max") == "359"
        first = page.evaluate("[window.camcadAnimation.frame, document.getElementById('camcad-cam')"
                              ".getAttribute('transform')]")
        page.wait_for_function(f"window.camcadAnimation.frame !== {first[0]}", timeout=10000)
        second = page.evaluate("document.getElementById('camcad-cam').getAttribute('transform')")
        assert first[1] != second and first[1].startswith("rotate(")       # it plays: the cam turns
        page.keyboard.press(" ")                                             # pause, then step by hand
        page.wait_for_function("window.camcadAnimation.playing === false")
        frame = page.evaluate("window.camcadAnimation.frame")
        page.keyboard.press("ArrowRight")
        assert page.evaluate("window.camcadAnimation.frame") == (frame + 1) % 360
        theta = page.inner_text("#camcad-theta")
        assert theta == f"{(frame + 1) % 360:.1f} deg"                        # the frame's cam angle, 1 deg a frame
        assert errors == []
    finally:
        page.close()


def test_every_check_row_of_the_report_equals_report_json(browser, handed_over):
    report = json.loads((handed_over / "report.json").read_text())
    expected = _checks_of(report)
    assert len(expected) >= 4
    page, errors = _page(browser, (handed_over / "report.html").as_uri())
    try:
        rows = page.eval_on_selector_all("tr[data-check]", "rows => rows.map(r => ({check: r.dataset.check, "
                                         "path: r.dataset.path, value: r.dataset.value, limit: r.dataset.limit, "
                                         "margin: r.dataset.margin, text: r.innerText}))")
        assert sorted(json.dumps(json.loads(row["path"])) for row in rows) == sorted(expected)
        for row in rows:
            check = expected[json.dumps(json.loads(row["path"]))]
            assert row["check"] == json.loads(row["path"])[-1]
            for key in ("value", "limit", "margin"):
                assert json.loads(row[key]) == check[key], (row["check"], key)
            assert ("ok" if check["passed"] else "FAIL") in row["text"]
        margins = [expected[json.dumps(json.loads(row["path"]))]["margin_ratio"] for row in rows]
        assert margins == sorted(margins)                                    # tightest first
        frame = page.frame_locator("iframe.animation")                       # the animation, inline, plays
        frame.locator("#camcad-mechanism[data-frames='360']").wait_for(timeout=20000)
        page.wait_for_timeout(500)
        assert errors == []
    finally:
        page.close()


def test_the_report_reads_on_a_phone(browser, handed_over):
    page, errors = _page(browser, (handed_over / "report.html").as_uri(), width=390, height=844)
    try:
        page.wait_for_load_state("load")
        width = page.evaluate("document.documentElement.scrollWidth")
        assert width <= 390, f"the page scrolls sideways on a phone: {width} px"
        assert errors == []
    finally:
        page.close()


def test_the_report_prints_to_pdf(cli, tmp_path):
    _chromium()
    result = cli("profile", "--report-pdf", "--no-plots", "-o", tmp_path)
    assert result.code == 0, result.err
    pdf = (tmp_path / "report.pdf").read_bytes()
    assert pdf.startswith(b"%PDF-") and len(pdf) > 10_000
    assert (tmp_path / "report.html").is_file()


def test_the_linkage_alone_plays_its_frames_without_a_console_error(browser, tmp_path):
    """`camcad linkage analyse --animate` of a four-bar given by options: 2 ceil(30 / 1) = 60 frames, it plays
    (the joint B moves), the keys step it, the readout shows the frame's swing, no console error."""
    from camcad.cli import main

    try:
        main(["linkage", "analyse", "--links", "40,120,90", "--output-pivot", "100,20", "--input-angle", "80",
              "--swing", "30", "--sense", "-1", "--coupler-point", "30,10", "--animate", "--no-plots", "-o",
              str(tmp_path)])
    except SystemExit as stop:
        assert int(stop.code or 0) == 0
    page, errors = _page(browser, (tmp_path / "animation.html").as_uri())
    try:
        page.wait_for_function("window.camcadAnimation && window.camcadAnimation.shown > 5", timeout=20000)
        assert page.get_attribute("#camcad-mechanism", "data-frames") == "60"
        assert page.evaluate("window.camcadAnimation.frames") == 60
        first = page.evaluate("[window.camcadAnimation.frame, document.getElementById('camcad-joint-B')"
                              ".getAttribute('cx')]")
        page.wait_for_function(f"window.camcadAnimation.frame !== {first[0]}", timeout=10000)
        assert page.evaluate("document.getElementById('camcad-joint-B').getAttribute('cx')") != first[1]
        page.keyboard.press(" ")
        page.wait_for_function("window.camcadAnimation.playing === false")
        page.keyboard.press("Home")
        while page.evaluate("window.camcadAnimation.frame") != 29:
            page.keyboard.press("ArrowRight")
        assert page.inner_text("#camcad-input") == "29.000 deg"               # out: 1 deg of swing a frame
        page.keyboard.press("ArrowRight")
        assert page.inner_text("#camcad-input") == "30.000 deg"               # the turn-back
        page.keyboard.press("ArrowRight")
        assert page.inner_text("#camcad-input") == "29.000 deg"
        if os.environ.get("CAMCAD_SCREENSHOT"):
            page.screenshot(path=os.environ["CAMCAD_SCREENSHOT"])
        assert errors == []
    finally:
        page.close()
