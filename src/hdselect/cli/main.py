"""Command line: a thin layer over the public API; it formats, it does not compute.

`main` makes SIGTERM unwind like Ctrl-C before it imports anything heavy (every command's
module, and through them numpy and Pinocchio, load after), so that a signal at any moment
of a run ends it with one line and status 130 or 143, and no output written.
"""

from __future__ import annotations

import argparse
import logging
import os
import signal
import sys
from collections.abc import Sequence

from hdselect import __version__
from hdselect.base.session import (
    EXIT_INTERRUPTED,
    EXIT_TERMINATED,
    HeldLog,
    Terminated,
    handle_sigterm,
    tolerate_encoding,
)

logger = logging.getLogger("hdselect")


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``hdselect`` command.

    Args:
        argv: The arguments after ``hdselect``; None: the program's own (``sys.argv``),
            and then a signal after the command has ended still exits 130 or 143.

    Returns:
        Exit status: 0 success, 1 no gearhead fits, 2 bad input (one line on standard
        error, no output), 3 some case of a study failed, 70 a bug in hdselect (one
        line; ``-v`` shows the traceback), 130 interrupted (Ctrl-C), 143 terminated
        (SIGTERM).
    """
    previous = handle_sigterm()  # first: the imports below take a while
    kept = _Kept()
    try:
        return _run(sys.argv[1:] if argv is None else argv, kept)
    except (KeyboardInterrupt, Terminated) as stop:
        if argv is None:
            _exit_on_signal()  # a second signal while this is said: no traceback
        interrupted = isinstance(stop, KeyboardInterrupt)
        _say(f"{'interrupted' if interrupted else 'terminated'}; {kept.text()}")
        status = EXIT_INTERRUPTED if interrupted else EXIT_TERMINATED
        if argv is None:  # Python ends a process whose Ctrl-C an import saw by SIGINT (-2)
            _leave(status)
        return status
    finally:
        if argv is None:  # the program: until it exits, a signal ends it quietly
            _exit_on_signal()
        elif previous is not None:
            signal.signal(signal.SIGTERM, previous)


def _run(argv: Sequence[str], kept: _Kept) -> int:
    """Parse, run the command and turn its errors into one line; the exit status."""
    import warnings

    from hdselect.base.errors import HdselectError
    from hdselect.catalog.builtin import catalog_files
    from hdselect.cli.inputs import toml_files_wanted
    from hdselect.cli.output import EXIT_BAD_INPUT, EXIT_BUG, EXIT_OK

    held = HeldLog(logger)
    try:
        tolerate_encoding()
        parser = _parser()
        argv = list(argv)
        args = parser.parse_args(argv)
        args.command_line = ["hdselect", *argv]
        args.kept, args.held = kept, held
        held.start(verbose=args.verbose)
        if getattr(args, "catalog", None):  # built-in names become their files
            args.catalog = catalog_files(args.catalog, field="--catalog")
        toml_files_wanted(args)
        # Python's and numpy's warnings too are held: a refusal stays one line (the
        # filters in force still apply; only where they print changes)
        with warnings.catch_warnings(record=True) as caught:
            status = int(args.run(args))
        held.publish()
        for text in dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught):
            _say(f"warning: {_one_line(text)}")
        return status
    except HdselectError as err:
        _say(f"error: {_one_line(str(err))}")
        return EXIT_BAD_INPUT
    except MemoryError:
        _say("error: out of memory; use a larger dt, a shorter cycle or a lower --max-samples")
        return EXIT_BAD_INPUT
    except BrokenPipeError:
        # The reader went away (e.g. `| head`): not an error of ours.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_OK
    except Exception as err:  # a bug: say so in one line, with the way to the traceback
        stop = _stop_within(err)
        if stop is not None:  # a signal an import turned into its own error: not a bug
            raise stop from err
        if held.verbose:
            import traceback

            traceback.print_exc()
        _say(f"internal error (a bug in hdselect, not in your input): {type(err).__name__}: "
             f"{_one_line(str(err))}; no output was written; run again with -v for the "
             "traceback")
        return EXIT_BUG
    finally:
        held.stop()


def _exit_on_signal() -> None:
    """After the command: SIGINT and SIGTERM end the process at once, 130 or 143, silently.

    The command's outputs are complete by then; what is left is the interpreter's exit.
    """
    def leave(signum: int, frame: object) -> None:
        _leave(EXIT_INTERRUPTED if signum == signal.SIGINT else EXIT_TERMINATED)

    for signum in (signal.SIGINT, signal.SIGTERM):
        try:
            if signal.getsignal(signum) is not signal.SIG_IGN:
                signal.signal(signum, leave)
        except ValueError:  # not the main thread: the signals are not ours to handle
            return


def _leave(status: int) -> None:
    """End the process now with `status`, its exit handlers run and its streams flushed."""
    import atexit

    atexit._run_exitfuncs()  # the copies of streams read (hdselect.base.inputfiles) go
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(status)


def _stop_within(err: BaseException) -> BaseException | None:
    """The Ctrl-C or SIGTERM an exception was raised from, if any (numpy's ImportError)."""
    seen: set[int] = set()
    cause: BaseException | None = err
    while cause is not None and id(cause) not in seen:
        if isinstance(cause, KeyboardInterrupt | Terminated):
            return cause
        seen.add(id(cause))
        cause = cause.__cause__ or cause.__context__
    return None


class _Kept:
    """What an interrupted command leaves behind: nothing, except a study's finished cases."""

    def __init__(self) -> None:
        self.note: str | None = None

    def text(self) -> str:
        return self.note or "no output was written"


def _say(message: str) -> None:
    # a name of undecodable bytes from the command line is shown escaped, on any stream
    text = f"hdselect: {message}".encode("utf-8", "backslashreplace").decode("utf-8")
    print(text, file=sys.stderr)


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _command(commands, verbose: argparse.ArgumentParser, name: str,
             summary: str) -> argparse.ArgumentParser:
    """A command's parser; its one-line summary heads both ``hdselect --help`` and its own."""
    return commands.add_parser(name, parents=[verbose], help=summary, allow_abbrev=False,
                               description=f"{summary[:1].upper()}{summary[1:]}.")


_OUTPUTS = ("json", "report", "bom", "out", "plot", "waypoints", "line_errors")
"""Options naming an output: an empty one is refused in the words of every output's check
(`hdselect.base.outputs.check_output_path`)."""


class _Parser(argparse.ArgumentParser):
    """Command-line errors as one line, like every other error, with exit status 2."""

    def error(self, message: str):  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")

    def parse_args(self, args=None, namespace=None):  # type: ignore[override]
        """Parse; an unknown option is refused by its command, with the option nearest it.

        Options are never abbreviated: ``size --joint J`` is not ``--joints J``.
        """
        parsed, extra = self.parse_known_args(args, namespace)
        if extra:
            import difflib

            command = self._subparsers._group_actions[0].choices.get(  # type: ignore[union-attr]
                getattr(parsed, "command", None), self) if self._subparsers else self
            known = [name for action in command._actions for name in action.option_strings]
            given = extra[0].split("=")[0]
            elsewhere = given.startswith("--") and any(  # another command's option
                given in action.option_strings for other in
                self._subparsers._group_actions[0].choices.values()  # type: ignore[union-attr]
                for action in other._actions) if self._subparsers else False
            nearest = difflib.get_close_matches(given, known, n=1, cutoff=0.9 if elsewhere
                                                else 0.6)
            hint = ((f"; {command.prog.split()[-1]} takes no {given}" if elsewhere else "")
                    + (f"; did you mean {nearest[0]}?" if nearest else ""))
            command.error(f"unrecognized arguments: {' '.join(extra)}{hint}")
        return parsed

    def parse_known_args(self, args=None, namespace=None):  # type: ignore[override]
        """Parse, then refuse an empty value of any option or argument.

        An empty value never means "not given" (``--velocity ''`` fell back to a default).
        """
        parsed, extra = super().parse_known_args(args, namespace)
        for action in self._actions:
            if action.nargs == 0 or isinstance(action, argparse._SubParsersAction):
                continue
            value = getattr(parsed, action.dest, None)
            if any(isinstance(item, str) and not item.strip()
                   for item in (value if isinstance(value, list) else [value])):
                name = max(action.option_strings, key=len, default=action.metavar
                           or action.dest)
                if action.dest in _OUTPUTS:  # an output's own words
                    from hdselect.base.outputs import check_output_path

                    check_output_path("", name, directory=action.dest == "report")
                self.error(f"argument {name}: expected a value, got an empty string")
        return parsed, extra


def _parser() -> argparse.ArgumentParser:
    from hdselect.cli.arguments import (
        catalog_argument,
        json_argument,
        margin_argument,
        robot_motion_arguments,
        scheduler_arguments,
        sizing_arguments,
        xacro_argument,
    )
    from hdselect.cli.catalog import run_catalog, run_duty
    from hdselect.cli.codesign import run_fastest, run_max_payload
    from hdselect.cli.envelope import envelope_arguments, run_envelope
    from hdselect.cli.plan import plan_arguments, run_plan
    from hdselect.cli.robot import run_init, run_joints
    from hdselect.cli.size import run_compare, run_size
    from hdselect.cli.study import run_study

    parser = _Parser(
        prog="hdselect", allow_abbrev=False,
        description="Size Harmonic Drive PSA-G gearheads for robot joints.",
        epilog="A first run on your own robot: hdselect joints ROBOT (its joints as read), "
               "hdselect init ROBOT --out motion.toml (a starter motion), hdselect size "
               "motion.toml. hdselect COMMAND --help says what a command takes.")
    parser.add_argument("--version", action="version", version=f"hdselect {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="print progress notes")
    verbose = _Parser(add_help=False)  # -v after the command too
    verbose.add_argument("-v", "--verbose", action="store_true", default=argparse.SUPPRESS,
                         help="print progress notes")
    commands = parser.add_subparsers(title="commands", required=True, metavar="COMMAND",
                                     dest="command", parser_class=_Parser)

    catalog = _command(commands, verbose, "catalog", "list the gearhead catalog")
    catalog_argument(catalog)
    catalog.add_argument("--units", choices=("si", "imperial"), default="si",
                         help="unit system of the table (default: si)")
    catalog.add_argument("--json", action="store_true", help="print JSON instead of a table")
    catalog.add_argument("--list", action="store_true",
                         help="list the built-in catalogs (load one with --catalog NAME)")
    catalog.set_defaults(run=run_catalog)

    duty = _command(commands, verbose, "duty",
                    "size from a torque-speed profile (catalog method)")
    duty.add_argument("profile", help="duty-cycle profile (TOML)")
    catalog_argument(duty)
    margin_argument(duty, motion=False)
    json_argument(duty)
    duty.set_defaults(run=run_duty)

    plan = _command(commands, verbose, "plan", "plan a motion and write its torques (CSV)")
    plan_arguments(plan)
    plan.set_defaults(run=run_plan)

    size = _command(commands, verbose, "size",
                    "choose a gearhead for every joint of a robot")
    robot_motion_arguments(size)
    sizing_arguments(size)
    json_argument(size)
    size.add_argument("--report", metavar="DIR",
                      help="write an HTML report with figures into DIR ('-': the page alone, "
                           "to stdout)")
    size.add_argument("--bom", metavar="CSV",
                      help="write the parts list: per joint the gearhead and motor, ratio, "
                           "masses, binding rule and margin, then the totals ('-': to stdout)")
    size.set_defaults(run=run_size)

    compare = _command(commands, verbose, "compare",
                       "every unit against every joint, side by side")
    shown = robot_motion_arguments(compare)
    shown.title = "joints sized (--joints, --exclude) and shown (--joint)"
    sizing_arguments(compare)
    shown.add_argument("--joint", action="append", metavar="JOINT",
                       help="show only this joint's table, JSON and report (repeatable); "
                            "the joints --joints names are all sized")
    json_argument(compare)
    compare.add_argument("--report", metavar="DIR",
                         help="write an HTML report of the joints shown into DIR ('-': the "
                              "page alone, to stdout)")
    compare.add_argument("--bom", metavar="CSV",
                         help="write the parts list of the selection, every joint (as size "
                              "--bom; '-': to stdout)")
    compare.set_defaults(run=run_compare)

    fastest = _command(commands, verbose, "fastest",
                       "the shortest cycle of the motion's path that the gearheads allow")
    compared = robot_motion_arguments(fastest)
    compared.title = "joints sized (--joints, --exclude) and compared (--joint)"
    sizing_arguments(fastest)
    fastest.add_argument("--units", action="append", metavar="JOINT=UNIT", default=[],
                         help="the unit of a joint, as `hdselect catalog` names it (repeatable; "
                              "default: the unit `size` selects)")
    fastest.add_argument("--compare-ratios", action="store_true",
                         help="the shortest cycle with every catalog unit on each joint, the "
                              "others fixed")
    compared.add_argument("--joint", action="append", metavar="JOINT",
                          help="with --compare-ratios: compare units on this joint only "
                               "(repeatable); the joints --joints names are all sized")
    fastest.add_argument("--out", metavar="FILE",
                         help="CSV of the fastest trajectory: t, then q_, qd_, qdd_, tau_ per "
                              "sized joint (SI)")
    fastest.add_argument("--plot", metavar="PNG",
                         help="speed and torque per joint; with --compare-ratios, cycle time "
                              "against unit")
    json_argument(fastest)
    fastest.set_defaults(run=run_fastest)

    payload = _command(commands, verbose, "max-payload",
                       "the largest payload with a feasible unit on every joint")
    robot_motion_arguments(payload, mass=False)
    payload.add_argument("--task", action="append", metavar="NAME",
                         help="with a mix file: scale this task's payload (repeatable; default: "
                              "every task that carries one)")
    sizing_arguments(payload)
    payload.add_argument("--units", action="append", metavar="JOINT=UNIT", default=[],
                         help="a fixed unit for a joint, as `hdselect catalog` names it "
                              "(repeatable; give every sized joint one; default: the unit "
                              "`size` selects at each payload)")
    json_argument(payload)
    payload.set_defaults(run=run_max_payload)

    spec = _command(commands, verbose, "envelope",
                    "a gearhead for every joint that holds for any motion within a spec")
    envelope_arguments(spec)
    spec.set_defaults(run=run_envelope)

    joints = _command(commands, verbose, "joints",
                      "list a robot's joints in the order lists use")
    joints.add_argument("robot", metavar="ROBOT", help="robot file, URDF, xacro or MJCF")
    xacro_argument(joints, motion=False)
    json_argument(joints)
    joints.set_defaults(run=run_joints)

    init = _command(commands, verbose, "init", "write a starter motion file for a robot")
    init.add_argument("robot", metavar="ROBOT", help="robot file, URDF, xacro or MJCF")
    xacro_argument(init, motion=False)
    init.add_argument("--out", metavar="FILE",
                      help="the motion file to write (default or '-': print it); an existing "
                           "file is never overwritten")
    init.add_argument("--tool-poses", action="store_true",
                      help="write the waypoints as tool poses in the world (solved for the "
                           "mounting by inverse kinematics), not as joint positions")
    init.set_defaults(run=run_init)

    study = _command(commands, verbose, "study", "run every case of a design study (TOML)")
    study.add_argument("study", metavar="STUDY", help="study file (TOML)")
    study.add_argument("--out", metavar="CSV", required=True,
                       help="rows, one per case and joint, appended as cases complete; a JSON "
                            "Lines record of each case is kept beside it (same name, .jsonl); "
                            "cases already there are skipped")
    study.add_argument("--workers", type=int, metavar="N",
                       help="worker processes (default: the cores here; 0: in this process); "
                            "with --scheduler local, Dask workers")
    scheduler_arguments(study)
    study.add_argument("--no-grouping", action="store_true",
                       help="size every case on its own, not from its group's shared basis")
    study.add_argument("--retry-failed", action="store_true",
                       help="run again the cases recorded as failed")
    study.add_argument("--plot", metavar="PNG",
                       help="draw the unit selected and its life per joint against the first "
                            "varied parameters")
    study.set_defaults(run=run_study)
    return parser
