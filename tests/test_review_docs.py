"""docs/review.md run as a user would, and the parts list (``--bom``) checked by hand."""

from __future__ import annotations

import csv
import io
import re
import shlex
from pathlib import Path

import pytest

from hdselect import size
from hdselect.cli.main import main
from hdselect.report.parts import PARTS_COLUMNS, parts_csv

ROOT = Path(__file__).resolve().parents[1]
DOC = (ROOT / "docs" / "review.md").read_text(encoding="utf-8")
BENCHTOP = ROOT / "trajectories" / "benchtop6_pick_place.toml"


def workdir(tmp_path: Path) -> Path:
    """A directory where the document's relative paths resolve and outputs land (``out/``)."""
    for name in ("robots", "trajectories", "motors"):
        (tmp_path / name).symlink_to(ROOT / name)
    (tmp_path / "out").mkdir()
    return tmp_path


def console_examples() -> list[tuple[str, str]]:
    examples = []
    for block in re.findall(r"```console\n(.*?)```", DOC, flags=re.S):
        command, *shown = block.rstrip("\n").split("\n")
        examples.append((command.removeprefix("$ "), "\n".join(shown)))
    return examples


@pytest.mark.parametrize(("command", "shown"), console_examples(), ids=lambda x: x[-60:])
def test_console_example_prints_what_the_document_shows(command, shown, tmp_path,
                                                        monkeypatch, capsys):
    monkeypatch.chdir(workdir(tmp_path))
    monkeypatch.setenv("COLUMNS", "80")
    args = shlex.split(command)
    assert args[0] == "hdselect"
    assert main(args[1:]) == 0
    printed = "\n".join(line.rstrip() for line in capsys.readouterr().out.rstrip().split("\n"))
    assert printed == shown.rstrip()


@pytest.mark.slow
def test_the_report_command_writes_the_summary_with_the_margin(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(workdir(tmp_path))
    (block,) = re.findall(r"```sh\n(.*?)```", DOC, flags=re.S)
    args = shlex.split(block.strip())
    assert main(args[1:]) == 0
    # issue 27: into out/, never into the repository's root
    assert [arg for arg in args if "review" in arg] == ["out/review"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["motors", "out", "robots",
                                                          "trajectories"]
    page = (tmp_path / "out" / "review" / "index.html").read_text(encoding="utf-8")
    summary = page[page.index("<section id=summary"):page.index("</section>")]
    assert "20 %: every rule must hold at up to 80 % of its limit" in summary
    assert "Warnings that change a decision" in summary and "Parts list" in page
    assert page.count("<details open") >= 8
    capsys.readouterr()


def test_the_documented_columns_are_the_csvs():
    table = DOC[DOC.index("| column | what |"):]
    documented = re.findall(r"^\| `([a-z0-9_]+)`(?:, `([a-z0-9_]+)`)? \|", table, flags=re.M)
    names = [name for pair in documented for name in pair if name]
    assert names == list(PARTS_COLUMNS)


def rows_of(text: str) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(text)))


def test_parts_list_by_hand_and_its_totals():
    """The benchtop arm without motors: PSA-08-100 (0.3 kg), PSA-14-100 (0.5), PSA-10-80
    (0.4), PSA-08-80 (0.3), PSA-08-100 (0.3), PSA-08-80 (0.3): 2.1 kg of gearheads, the
    catalog's masses; each row's margin left is 1 - its binding utilization."""
    result = size(None, BENCHTOP)
    rows = rows_of(parts_csv(result))
    assert list(rows[0]) == list(PARTS_COLUMNS)
    *joints, total = rows
    assert [r["gearhead"] for r in joints] == ["PSA-08-100", "PSA-14-100", "PSA-10-80",
                                               "PSA-08-80", "PSA-08-100", "PSA-08-80"]
    assert [float(r["gearhead_mass_kg"]) for r in joints] == [0.3, 0.5, 0.4, 0.3, 0.3, 0.3]
    assert total["joint"] == "total" and float(total["gearhead_mass_kg"]) == pytest.approx(2.1)
    assert float(total["mass_kg"]) == pytest.approx(2.1) and total["status"] == (
        "every joint has a unit")
    for row, joint in zip(joints, result.joints, strict=True):
        chosen = joint.selected
        assert row["binding"] == chosen.binding
        assert float(row["utilization"]) == pytest.approx(
            chosen.checks[chosen.binding].utilization, rel=1e-5)
        assert float(row["margin_left"]) == pytest.approx(
            1.0 - float(row["utilization"]), abs=2e-6)
        assert float(row["ratio"]) == chosen.unit.ratio and row["motor"] == ""


@pytest.mark.slow
def test_parts_list_with_motors_and_a_joint_no_unit_fits(tmp_path):
    """Pairs: the motor ids and masses from the motor file, summed. A 4 kg payload leaves
    a joint without a unit: its row is empty but for the joint, and the total counts it."""
    motors = ROOT / "motors" / "example_motors.toml"
    out = tmp_path / "parts.csv"
    assert main(["size", str(BENCHTOP), "--motor-catalog", str(motors), "--bom", str(out)]) == 0
    *joints, total = rows_of(out.read_text())
    masses = {"EX-16": 0.06, "EX-22": 0.11, "EX-32": 0.18, "EX-40": 0.28, "EX-45F": 0.34,
              "EX-50F": 0.45}
    assert all(r["motor"] in masses for r in joints)
    assert float(total["motor_mass_kg"]) == pytest.approx(sum(masses[r["motor"]]
                                                              for r in joints))
    for r in joints:
        assert float(r["mass_kg"]) == pytest.approx(float(r["gearhead_mass_kg"])
                                                    + float(r["motor_mass_kg"]))
        assert float(r["inertia_ratio"]) > 0.0
    assert main(["compare", str(BENCHTOP), "--payload", "4", "--bom", str(out)]) == 1
    *joints, total = rows_of(out.read_text())
    missing = [r for r in joints if r["status"].startswith("no unit fits: ")]
    assert missing and all(r["gearhead"] == "" and r["mass_kg"] == "" for r in missing)
    assert all(" N m" in r["status"] and r["binding"] and float(r["utilization"]) > 1.0
               for r in missing)  # the shortfall, not an empty row
    assert total["status"] == f"{len(missing)} joint{'s' if len(missing) > 1 else ''} without " \
        "a unit"


def test_a_bad_bom_path_is_refused_before_any_work(tmp_path, capsys):
    assert main(["size", str(BENCHTOP), "--bom", str(tmp_path / "missing" / "x.csv")]) == 2
    err = capsys.readouterr().err
    assert "--bom" in err and len(err.strip().splitlines()) == 1
