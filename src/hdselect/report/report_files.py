"""The HTML report written: the page, its figures embedded and as PNG files beside it."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from hdselect.base.errors import InputError
from hdselect.base.outputs import Outputs
from hdselect.report.bearing_figures import bearing_figure
from hdselect.report.figures import png_bytes
from hdselect.report.joint_figures import joint_figure, motor_figure
from hdselect.report.precision_figures import precision_figures
from hdselect.sizing.diagnosis import with_diagnoses
from hdselect.sizing.result import SizingResult


def write_report(directory: str | Path, result: SizingResult, *,
                 command: Sequence[str] | None = None) -> None:
    """Write the HTML report into `directory`: ``index.html``, self-contained, and its figures.

    ``index.html`` embeds every figure, so it can be mailed or printed on its own;
    the figures are also written beside it as ``joint_<name>.png`` (and, for a joint
    with motors, its motor's torque-speed plane as ``motor_<name>.png``; where the
    bearing loads were computed, their figure as ``bearing_<name>.png``). Every file is
    written aside first and the whole report moved into place at the end
    (`hdselect.base.outputs`): a failure leaves no part of it, and puts back any file it
    would have replaced.

    Args:
        directory: Where to write; made (with its parents) if missing.
        result: The sizing result.
        command: The command line that made the result (program name first), recorded
            so that the report can be re-run; None from Python.

    Raises:
        InputError: The directory cannot be written.
    """
    with Outputs() as outputs:
        staging = outputs.directory(directory, "--report")
        report_files(staging, result, command=command)
        outputs.commit()


def report_files(directory: Path, result: SizingResult, *,
                 command: Sequence[str] | None = None) -> None:
    """Write the report's files into an existing (staging) directory, as `write_report` does.

    Raises:
        InputError: A file cannot be written.
    """
    from hdselect.report.html import slug

    page, figures, motor_figures, bearing_figures, precision = _report(result, command)
    try:
        for prefix, pngs in (("joint", figures), ("motor", motor_figures),
                             ("bearing", bearing_figures), ("precision", precision)):
            for name, png in pngs.items():
                (directory / f"{prefix}_{slug(name)}.png").write_bytes(png)
        (directory / "index.html").write_text(page, encoding="utf-8")
    except OSError as err:
        raise InputError(f"cannot write the report ({err.strerror})", path=directory,
                         field="--report") from err


def report_page(result: SizingResult, *, command: Sequence[str] | None = None) -> str:
    """The HTML report as one self-contained page, its figures embedded (``--report -``)."""
    return _report(result, command)[0]


def _report(result: SizingResult, command: Sequence[str] | None
            ) -> tuple[str, dict[str, bytes], dict[str, bytes], dict[str, bytes],
                       dict[str, bytes]]:
    """The page, each joint's torque, motor and bearing figures, and the precision figures.

    The joints' figures are PNG content by joint name, the precision figures by their name.
    """
    from hdselect.report.html import page
    from hdselect.report.provenance import provenance

    result = with_diagnoses(result)
    origin = provenance(result, command)
    figures = {joint.name: png_bytes(joint_figure(result, joint)) for joint in result.joints}
    motor_figures = {joint.name: png_bytes(motor_figure(result, joint))
                     for joint in result.joints if joint.motor_torque is not None}
    bearing_figures = {joint.name: png_bytes(fig) for joint in result.joints
                       if (fig := bearing_figure(result, joint)) is not None}
    precision = {name: png_bytes(fig) for name, fig in precision_figures(result).items()}
    return (page(result, figures, origin, motor_figures, bearing_figures, precision), figures,
            motor_figures, bearing_figures, precision)
