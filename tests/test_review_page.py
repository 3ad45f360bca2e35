"""The report as a design review reads it: the summary page first, every table on its page.

The shipped example report (docs/example-report: `hdselect size
trajectories/benchtop6_pick_place.toml --report docs/example-report`), a report with
motors and a report of a robot's working day (a mix of two tasks, with motors) are rendered
in Chromium at 1280 px, at a phone's width, and laid out for print on A4 and Letter
(12 mm margins: 186 mm and 191.9 mm of width, 273 mm and 255.4 mm of height); no
element may reach beyond the page, no table may hide a column behind a scroll bar,
the summary must fit one printed page, and a section folded on screen still prints.
"""

from __future__ import annotations

import base64
import re
import shutil
import subprocess

import pytest

from browser import Browser, chromium
from hdselect.cli.main import main
from helpers import REPO

EXAMPLE = REPO / "docs" / "example-report"
MOTORS = REPO / "motors" / "example_motors.toml"
BENCHTOP = REPO / "trajectories" / "benchtop6_pick_place.toml"
PICK_INSPECT = REPO / "trajectories" / "mixes" / "benchtop6_pick_inspect.toml"
PX_PER_MM = 96 / 25.4
PAPERS = {"A4": (210.0, 297.0), "Letter": (215.9, 279.4)}
MARGIN_MM = 12.0

OVERFLOW = """(() => {
  const width = document.documentElement.clientWidth, wide = [];
  for (const el of document.querySelectorAll('body *')) {
    const box = el.getBoundingClientRect();
    if (box.width === 0 && box.height === 0) continue;
    if (box.right > width + 0.5 || box.left < -0.5)
      wide.push(`${el.tagName}.${el.className} in ${(el.closest('section') || {}).id}`);
  }
  for (const el of document.querySelectorAll('body *'))
    if (el.scrollWidth > el.clientWidth + 1 && getComputedStyle(el).overflowX !== 'visible')
      wide.push(`scrolls: ${el.tagName}.${el.className}`);
  return [width, document.documentElement.scrollWidth, wide];
})()"""
"""Every element wider than the page, or scrolling sideways, by tag, class and section."""


@pytest.fixture(scope="module")
def browser():
    executable = chromium()
    if executable is None:
        pytest.skip("no Chromium here: `apt-get install chromium` (or set HDSELECT_CHROMIUM) "
                    "to render the report in a browser")
    try:
        opened = Browser(executable)
    except (OSError, RuntimeError, TimeoutError) as err:
        pytest.skip(f"Chromium at {executable} did not start: {err}")
    with opened:
        yield opened


@pytest.fixture(scope="module")
def motor_report(tmp_path_factory):
    """The benchtop arm with the example motors, at most 10:1 inertia, margin 0.1."""
    out = tmp_path_factory.mktemp("pairs") / "report"
    assert main(["size", str(BENCHTOP), "--motor-catalog", str(MOTORS), "--max-inertia-ratio",
                 "10", "--margin", "0.1", "--report", str(out)]) == 0
    return out / "index.html"


@pytest.fixture(scope="module")
def mix_report(tmp_path_factory):
    """The benchtop arm's day (pick 70 %, inspect 30 %), example motors, 10:1, margin 0.1."""
    out = tmp_path_factory.mktemp("mix") / "report"
    assert main(["size", str(PICK_INSPECT), "--motor-catalog", str(MOTORS),
                 "--max-inertia-ratio", "10", "--margin", "0.1", "--report", str(out)]) == 0
    return out / "index.html"


def laid_out(browser, page, media: str, width: int, *, mobile: bool = False):
    browser.send("Emulation.setDeviceMetricsOverride", session=True, width=width, height=900,
                 deviceScaleFactor=1, mobile=mobile)
    browser.send("Emulation.setEmulatedMedia", session=True, media=media)
    browser.load(page.resolve().as_uri())


def reset(browser):
    browser.send("Emulation.clearDeviceMetricsOverride", session=True)
    browser.send("Emulation.setEmulatedMedia", session=True, media="")


@pytest.mark.slow
@pytest.mark.parametrize("which", ["example", "motors", "mix"])
def test_every_table_fits_at_1280_px_on_a_phone_and_on_a4_and_letter(browser, motor_report,
                                                                     mix_report, which,
                                                                     tmp_path):
    page = {"example": EXAMPLE / "index.html", "motors": motor_report, "mix": mix_report}[which]
    widths = [("screen", 1280, False), ("screen", 390, True),
              *(("print", round((w - 2 * MARGIN_MM) * PX_PER_MM), False)
                for w, _ in PAPERS.values())]
    try:
        for media, width, mobile in widths:
            laid_out(browser, page, media, width, mobile=mobile)
            shown, scrolled, wide = browser.evaluate(OVERFLOW)
            assert shown == width and scrolled <= width, (media, width)
            assert wide == [], (media, width, wide[:5])
            if media == "screen":  # the first screen of it, for a person to look at
                shot = browser.send("Page.captureScreenshot", session=True, format="png")
                (tmp_path / f"{which}-{width}.png").write_bytes(base64.b64decode(shot["data"]))
    finally:
        reset(browser)


@pytest.mark.slow
@pytest.mark.parametrize("paper", list(PAPERS))
@pytest.mark.parametrize("which", ["example", "mix"])
def test_the_summary_is_one_printed_page_and_folded_sections_still_print(browser, mix_report,
                                                                         paper, which):
    """Laid out for print, the summary is at most one page tall (the page's height less its
    margins) and is followed by a page break; a section the reader folded prints in full.
    A mix's summary lists its tasks too, and still fits."""
    width, height = PAPERS[paper]
    try:
        laid_out(browser, EXAMPLE / "index.html" if which == "example" else mix_report,
                 "print", round((width - 2 * MARGIN_MM) * PX_PER_MM))
        top, bottom, brk = browser.evaluate(
            "(() => { const s = document.querySelector('#summary').getBoundingClientRect();"
            " const h = document.querySelector('h1').getBoundingClientRect();"
            " return [h.top, s.bottom, getComputedStyle(document.querySelector('#summary'))"
            ".breakAfter]; })()")
        assert bottom - top <= (height - 2 * MARGIN_MM) * PX_PER_MM
        assert brk == "page"
        folded = browser.evaluate(
            "(() => { for (const d of document.querySelectorAll('details')) d.open = false;"
            " return [...document.querySelectorAll('details > section')].map("
            "(s) => [s.id || s.className, s.getBoundingClientRect().height]); })()")
        assert len(folded) >= 8 and all(h > 0 for _, h in folded), folded
    finally:
        reset(browser)


@pytest.mark.slow
def test_the_printed_pdf_holds_every_column_and_a_summary_page(browser, tmp_path):
    """Printed from Chromium as a reader would (A4, then Letter): every column header of
    every table and every joint's verdict is in the PDF's text, the summary on page 1."""
    browser.load((EXAMPLE / "index.html").resolve().as_uri())
    headers = browser.evaluate(
        "[...new Set([...document.querySelectorAll('th')].map((th) => th.textContent"
        ".replace(/\\s+/g, ' ').trim()))]")
    for paper, (width, height) in PAPERS.items():
        data = browser.send("Page.printToPDF", session=True, printBackground=True,
                            paperWidth=width / 25.4, paperHeight=height / 25.4,
                            marginTop=0, marginBottom=0, marginLeft=0, marginRight=0)["data"]
        pdf = tmp_path / f"{paper}.pdf"
        pdf.write_bytes(base64.b64decode(data))
        pages = len(re.findall(rb"/Type\s*/Page\b", pdf.read_bytes()))
        assert 8 <= pages <= 14, (paper, pages)
        if shutil.which("pdftotext") is None:
            continue  # the layout checks above stand; the text check needs poppler-utils
        text = subprocess.run(["pdftotext", str(pdf), "-"], capture_output=True, text=True,
                              check=True).stdout
        squeezed = re.sub(r"\s+", " ", text)
        missing = [h for h in headers if h and h not in squeezed]
        assert missing == [], (paper, missing)
        first = subprocess.run(["pdftotext", "-f", "1", "-l", "1", str(pdf), "-"],
                               capture_output=True, text=True, check=True).stdout
        assert "Review summary" in first and "Warnings that change a decision" in first
        assert "Assumptions" in first and "Utilization of every candidate" not in first
