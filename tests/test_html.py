"""The HTML report: self-contained, its heat maps true to the checks, re-runnable, and as a
browser shows and prints it (where Chromium is installed)."""

from __future__ import annotations

import base64
import hashlib
import re
import shlex
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

from browser import Browser, chromium
from hdselect.cli.main import main
from hdselect.report.colours import FAIL_COLOURS, PASS_COLOURS, utilization_colour
from helpers.robots import LONG, ros_arm

CREATED = re.compile(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ")


class Cells(HTMLParser):
    """Every heat-map cell: (section id, joint, unit, check) -> its class."""

    def __init__(self) -> None:
        super().__init__()
        self.section = ""
        self.cells: dict[tuple[str, str, str, str], str] = {}

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "section":
            self.section = "heatmap" if a.get("id") == "heatmap" else a.get("class") or ""
        if tag == "td" and "data-check" in a:
            key = (self.section, a["data-joint"], a["data-unit"], a["data-check"])
            self.cells[key] = a["class"]


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    """`hdselect size --report` on the arm no shoulder unit fits, and its result."""
    import hdselect

    directory = tmp_path_factory.mktemp("html")
    motion = ros_arm(directory)
    out = directory / "report"
    assert main(["size", str(motion), "--report", str(out)]) == 1
    return out, hdselect.size(None, motion)


def failing(result) -> set[tuple[str, str, str]]:
    return {(j.name, c.unit.id, name) for j in result.joints for c in j.candidates
            for name, check in c.checks.items() if not check.ok}


def test_the_colour_scale_changes_character_at_the_limit():
    def rgb(colour):
        return tuple(int(colour[i:i + 2], 16) for i in (1, 3, 5))

    below, above = rgb(utilization_colour(0.999)), rgb(utilization_colour(1.001))
    assert below[2] > below[0] and above[0] > above[2]  # blue, then orange
    assert utilization_colour(0.0) == PASS_COLOURS[0][1]
    assert utilization_colour(1.0) == PASS_COLOURS[-1][1]
    assert utilization_colour(5.0) == FAIL_COLOURS[-1][1]  # clipped at 200 %
    darkness = [sum(rgb(utilization_colour(u))) for u in (0.0, 0.3, 0.6, 0.9)]
    assert darkness == sorted(darkness, reverse=True)  # darker towards the limit


@pytest.mark.slow
def test_heat_maps_mark_exactly_the_failing_checks(report):
    out, result = report
    cells = Cells()
    cells.feed((out / "index.html").read_text())
    for section in ("heatmap", "joint"):
        marked = {key[1:] for key, cls in cells.cells.items()
                  if key[0] == section and "fail" in cls.split()}
        assert marked == failing(result), section
        shown = {key[1:] for key in cells.cells if key[0] == section}
        assert shown >= marked and len(shown) > len(marked)


def test_the_page_is_self_contained_and_links_its_notes(report):
    out, result = report
    page = (out / "index.html").read_text()
    assert '<meta name="viewport"' in page
    assert "<script" not in page and "@import" not in page and "url(" not in page
    images = re.findall(r"src='data:image/png;base64,([A-Za-z0-9+/=]+)'", page)
    assert len(images) == 2 * len(result.joints)  # the profiles and the bearing, per joint
    for data in images:
        assert base64.b64decode(data)[:8] == b"\x89PNG\r\n\x1a\n"
    for anchor in set(re.findall(r'href="#(note-[^"]+)"', page)):
        assert f'id="{anchor}"' in page  # every * leads to its note
    assert 'href="#note-PSA-08-80"' in page and "momentary limit not rated" in page


class Sections(HTMLParser):
    """The text of each list item and each table row, by section id; a row's failing cells."""

    def __init__(self) -> None:
        super().__init__()
        self.section = ""
        self.items: dict[str, list[str]] = {}
        self.rows: dict[str, list[list[str]]] = {}
        self.failing: dict[str, list[tuple[int, int]]] = {}
        self._text: list[str] | None = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "section":
            self.section = a.get("id") or ""
        elif tag == "li":
            self._text = []
        elif tag == "tr":
            self.rows.setdefault(self.section, []).append([])
        elif tag in ("td", "th"):
            row = self.rows[self.section][-1]
            if "fail" in (a.get("class") or "").split():
                self.failing.setdefault(self.section, []).append(
                    (len(self.rows[self.section]) - 1, len(row)))
            row.append("")

    def handle_endtag(self, tag):
        if tag == "li" and self._text is not None:
            self.items.setdefault(self.section, []).append("".join(self._text))
            self._text = None

    def handle_data(self, data):
        if self._text is not None:
            self._text.append(data)
        elif self.rows.get(self.section) and self.rows[self.section][-1]:
            self.rows[self.section][-1][-1] += data


def test_the_page_has_the_base_the_warnings_and_every_joint_beside_its_file_limits(report):
    out, result = report
    page = Sections()
    page.feed((out / "index.html").read_text())
    assert page.items["warnings"] == list(result.warnings)
    assert any(w.startswith("cycle: ") for w in result.warnings)  # the arm is overloaded
    header, *rows = page.rows["loads"]
    assert header[:4] == ["joint", "type", "sized", "peak torque or force"]
    assert [row[0] for row in rows] == [load.name for load in result.loads]
    over = {(k + 1, 3) for k, load in enumerate(result.loads) if load.above_effort}
    over |= {(k + 1, 5) for k, load in enumerate(result.loads) if load.above_velocity}
    assert over and set(page.failing["loads"]) == over
    for row, column in over:
        assert rows[row - 1][column].endswith("✗")
    assert "joint losses" in "".join(page.items["assumptions"])
    assert "base: 'base_link' held fixed; payload: 1.5 kg on 'tool'" in "".join(
        (out / "index.html").read_text().replace("&#x27;", "'").split("\n"))


@pytest.mark.slow
def test_provenance_hashes_every_input_and_rerunning_reproduces_the_page(report, capsys):
    out, result = report
    page = (out / "index.html").read_text()
    for path in (result.robot.path, result.motion.path, *{u.source for u in result.units}):
        assert hashlib.sha256(Path(path).read_bytes()).hexdigest() in page
    for name in LONG.values():
        assert name in page
    assert "1.5 kg on tool" in page  # the resolved payload
    (command,) = re.findall(r"<pre id=command>(.*?)</pre>", page)
    args = shlex.split(command.replace("&#x27;", "'").replace("&quot;", '"'))
    assert args[0] == "hdselect" and args[1] == "size"
    assert main(args[1:]) == 1
    capsys.readouterr()
    again = (out / "index.html").read_text()
    assert CREATED.sub("T", again) == CREATED.sub("T", page)
    assert CREATED.search(page)


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


@pytest.mark.slow
def test_a_browser_shows_and_prints_the_report(report, browser, tmp_path):
    out, result = report
    url = (out / "index.html").resolve().as_uri()
    browser.load(url)
    sizes = browser.evaluate("Promise.all([...document.images].map(async (i) => {"
                             "await i.decode(); return [i.naturalWidth, i.naturalHeight]; }))")
    assert len(sizes) == 2 * len(result.joints) and all(w > 500 and h > 300 for w, h in sizes)
    cells = browser.evaluate(
        "[...document.querySelectorAll('td.u:not(.na)')].map((td) => [td.closest('section').id"
        " === 'heatmap', td.dataset.joint, td.dataset.unit, td.dataset.check, "
        "td.classList.contains('fail'), td.textContent.includes('✗'), "
        "getComputedStyle(td).backgroundImage !== 'none', getComputedStyle(td).backgroundColor])")
    expected = failing(result)
    for overview in (True, False):
        shown = [c for c in cells if c[0] is overview]
        assert {tuple(c[1:4]) for c in shown if c[4]} == expected
        for _, _, _, _, fail, cross, hatched, colour in shown:
            assert fail == cross == hatched  # marked three ways, never one alone
            r, _, b = (int(v) for v in re.findall(r"\d+", colour)[:3])
            assert (r > b) == fail  # orange over the limit, blue within
    browser.screenshot(tmp_path / "report.png")
    browser.pdf(tmp_path / "report.pdf")
    assert (tmp_path / "report.png").read_bytes()[:4] == b"\x89PNG"
    pdf = (tmp_path / "report.pdf").read_bytes()
    assert pdf[:4] == b"%PDF" and len(re.findall(rb"/Type\s*/Page\b", pdf)) >= 1 + len(
        result.joints)
    errors = [e for e in browser.events if e.get("method") == "Runtime.exceptionThrown"
              or (e.get("method") == "Runtime.consoleAPICalled"
                  and e["params"]["type"] in ("error", "warning"))
              or (e.get("method") == "Log.entryAdded"
                  and e["params"]["entry"]["level"] in ("error", "warning"))]
    assert errors == []
    requests = [e["params"]["request"]["url"] for e in browser.events
                if e.get("method") == "Network.requestWillBeSent"]
    assert requests and all(u == url or u.startswith("data:") for u in requests)


@pytest.mark.slow
def test_a_phone_sized_window_scrolls_tables_not_the_page(report, browser, tmp_path):
    out, _ = report
    browser.send("Emulation.setDeviceMetricsOverride", session=True, width=420, height=900,
                 deviceScaleFactor=1, mobile=True)
    try:
        browser.load((out / "index.html").resolve().as_uri())
        width, inner = browser.evaluate(
            "[document.documentElement.scrollWidth, window.innerWidth]")
        browser.screenshot(tmp_path / "report-phone.png")
    finally:
        browser.send("Emulation.clearDeviceMetricsOverride", session=True)
    assert width <= inner


@pytest.mark.slow
def test_a_report_from_python_says_so_and_hashes_a_logged_trajectory(tmp_path):
    import hdselect
    from hdselect.report.provenance import provenance
    from hdselect.report.report_files import write_report
    from helpers import REPO

    result = hdselect.size(None, REPO / "trajectories" / "pan_tilt_logged.toml")
    origin = provenance(result)
    roles = {f.role: f for f in origin.files}
    log = result.motion.samples.path
    assert roles["samples"].sha256 == hashlib.sha256(log.read_bytes()).hexdigest()
    assert roles["samples"].size == log.stat().st_size
    assert origin.command is None and origin.waypoints == ((), ())
    write_report(tmp_path / "r", result)
    page = (tmp_path / "r" / "index.html").read_text()
    assert "Made through the Python API" in page and "<pre id=command>" not in page
    assert roles["samples"].sha256 in page and "samples" in page


# --- gearhead and motor pairs ------------------------------------------------------------

EXAMPLE_MOTORS = Path(__file__).resolve().parents[1] / "motors" / "example_motors.toml"


class PairCells(HTMLParser):
    """Every heat-map cell of a report with motors: (section, joint, unit, motor, check)."""

    def __init__(self) -> None:
        super().__init__()
        self.section = ""
        self.cells: dict[tuple[str, str, str, str, str], str] = {}

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "section":
            self.section = "heatmap" if a.get("id") == "heatmap" else a.get("class") or ""
        if tag == "td" and "data-check" in a:
            key = (self.section, a["data-joint"], a["data-unit"], a["data-motor"],
                   a["data-check"])
            self.cells[key] = a["class"]


@pytest.fixture(scope="module")
def pair_report(tmp_path_factory):
    """`hdselect size --motor-catalog --report` on the arm no shoulder pair fits."""
    import hdselect

    directory = tmp_path_factory.mktemp("pairs")
    motion = ros_arm(directory)
    out = directory / "report"
    assert main(["size", str(motion), "--motor-catalog", str(EXAMPLE_MOTORS),
                 "--report", str(out)]) == 1
    motors = hdselect.load_motors(EXAMPLE_MOTORS)
    return out, hdselect.size(None, motion, motors={name: motors for name in LONG.values()})


@pytest.mark.slow
def test_pair_heat_maps_mark_exactly_the_failing_checks_of_both_sides(pair_report):
    out, result = pair_report
    page = (out / "index.html").read_text()
    cells = PairCells()
    cells.feed(page)
    expected = {(j.name, c.unit.id, c.motor_unit.id, name) for j in result.joints
                for c in j.candidates for name, check in c.checks.items() if not check.ok}
    assert any(name.startswith("motor_") for *_, name in expected)
    for section in ("heatmap", "joint"):
        marked = {key[1:] for key, cls in cells.cells.items()
                  if key[0] == section and "fail" in cls.split()}
        assert marked == expected, section
        shown = {key[1:] for key in cells.cells if key[0] == section}
        assert len(shown) == sum(len(j.candidates) for j in result.joints) * len(
            {key[4] for key in cells.cells})  # a cell per pair and check
    assert "Gearhead and motor selection" in page and "no pair fits" in page


def test_pair_report_embeds_each_motor_figure_and_hashes_the_motor_file(pair_report):
    out, result = pair_report
    page = (out / "index.html").read_text()
    images = re.findall(r"src='data:image/png;base64,([A-Za-z0-9+/=]+)'", page)
    assert len(images) == 3 * len(result.joints)  # the profiles, the motor, the bearing
    for joint in result.joints:
        shown = joint.selected or joint.strongest
        motor_png = (out / f"motor_{joint.name}.png").read_bytes()
        assert base64.b64encode(motor_png).decode("ascii") in images
        assert f"torque-speed plane of the motor {shown.motor_unit.id} of {joint.name}" in page
    assert hashlib.sha256(EXAMPLE_MOTORS.read_bytes()).hexdigest() in page
    assert "every sized joint chooses from EX-16, EX-22" in page
    assert "no thermal model" in page and "load/rotor inertia" in page


@pytest.mark.slow
def test_a_browser_shows_the_pair_report(pair_report, browser, tmp_path):
    out, result = pair_report
    browser.load((out / "index.html").resolve().as_uri())
    sizes = browser.evaluate("Promise.all([...document.images].map(async (i) => {"
                             "await i.decode(); return [i.naturalWidth, i.naturalHeight]; }))")
    assert len(sizes) == 3 * len(result.joints) and all(w > 500 and h > 300 for w, h in sizes)
    marks = browser.evaluate(
        "[...document.querySelectorAll('td.u:not(.na)')].map((td) => ["
        "td.classList.contains('fail'), td.textContent.includes('✗'), "
        "getComputedStyle(td).backgroundImage !== 'none'])")
    assert marks and all(fail == cross == hatched for fail, cross, hatched in marks)
    assert any(fail for fail, _, _ in marks)
    browser.screenshot(tmp_path / "pairs.png")
    errors = [e for e in browser.events if e.get("method") == "Runtime.exceptionThrown"
              or (e.get("method") == "Log.entryAdded"
                  and e["params"]["entry"]["level"] in ("error", "warning"))]
    assert errors == []


def test_the_case_as_run_says_what_an_option_left_unset_means():
    """No `None` in what a reader sees: threads and life say what they stand for."""
    import hdselect
    from hdselect.report.provenance import provenance
    from helpers import REPO

    robot, motion = hdselect.load_case(REPO / "trajectories" / "planar2_pick_place.toml")
    result = hdselect.size_trajectory(robot, hdselect.plan(robot, motion),
                                      hdselect.load_catalog(), hdselect.Options())
    assert result.options.threads is None and result.options.life_hours is None
    (options,) = [value for what, value in provenance(result).settings if what == "options"]
    assert "None" not in options
    assert "threads = automatic (up to the cores)" in options
    assert "life_hours = none required" in options
    assert f"prefer = {result.options.prefer}" in options


@pytest.mark.slow
def test_the_report_package_gives_write_report_without_importing_matplotlib():
    code = ("import sys, hdselect.report as r; assert 'matplotlib' not in sys.modules; "
            "from hdselect.report.report_files import report_page, write_report; "
            "assert r.write_report is write_report and r.report_page is report_page")
    subprocess.run([sys.executable, "-c", code], check=True)
