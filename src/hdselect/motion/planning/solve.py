"""A motion's tool poses solved for one robot and mounting: an ordinary joint motion.

Each pose is carried from the world into the robot's base frame through its mounting
(`Robot.base_pose`) and solved by inverse kinematics (`hdselect.ik.solver`), seeded from
the waypoint before (the first from the middle of the joint ranges), with the
waypoint's ``near`` hint applied; up to `RESTARTS` random restarts follow when that seed
fails; when the solution is on another branch than the waypoint before, other seeds
look for one on the same branch (unless the waypoint's ``near`` chose the branch, which
must then be honoured: `hdselect.motion.planning.hints.honour`). A pose that fixes less
than a full pose (`hdselect.ik.targets.Target`: an approach axis, a yaw, a position
alone) is solved on the rows it fixes, its free coordinates reported per waypoint
(`ToolSolution.free`). A line
(``line = true``) is walked from the waypoint before
(`hdselect.ik.lines`), and its samples refined until the planner's spline follows
it (`hdselect.motion.planning.linefit`).

Every move into or out of a solved pose is checked for a change of branch
(`hdselect.ik.branches`). A change is an error unless the waypoint says
``reconfigure = true``: a reconfiguration swings joints through large angles that the
task, as written, does not need, so sizing it silently would size another task. The
message names the waypoints and how to keep the branch (a ``near`` hint).

A cycle back at its first pose with joints whole turns away (a wrist at +180 deg, then
-180 deg) is closed with the first's joints, or refused (`_Solver._close_cycle`); so is
one back at a first pose that fixes less, where the first's joints meet it.

Joint waypoints keep their joint positions whatever the mounting: on any mounting but
the floor they move with the robot, and a note says so.
"""

from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np

from hdselect.base.arrays import frozen
from hdselect.base.bounds import expect_type
from hdselect.base.errors import InputError
from hdselect.ik.branches import check_branch, whole_turns
from hdselect.ik.lines import LinePath, LineStop, solve_line
from hdselect.ik.poses import base_in_world, in_base
from hdselect.ik.solver import PoseSolution, solve_pose
from hdselect.ik.targets import Goal, Target, goal_error, goal_in
from hdselect.motion.motionfile import Motion
from hdselect.motion.planning.hints import Words, honour
from hdselect.motion.planning.linefit import fit_lines
from hdselect.motion.toolposes import PoseWaypoint, ToolPoses, ToolSolution
from hdselect.robot.kinematics import FrameKinematics
from hdselect.robot.model import Robot
from hdselect.robot.mounting import NAMED_BASES, BasePose, mounting_name

logger = logging.getLogger(__name__)

RESTARTS = 8
"""Random restarts of a pose whose seeded solve fails [-]."""
BRANCH_SEEDS = 24
"""Further seeds tried when a pose's solution is on another branch than the waypoint
before: around that waypoint's joints, then anywhere within the limits [-]."""


def solve_motion(robot: Robot, motion: Motion) -> Motion:
    """The motion as joint waypoints for this robot as it is mounted.

    A motion without tool poses comes back as it is (with a note when the robot is not
    on the floor); one already solved for the same robot file, joint limits, frame and
    mounting comes back as it is.

    Args:
        robot: The robot as the motion runs it (payload and mounting applied).
        motion: The motion read for its joints.

    Returns:
        The motion with every waypoint in joint positions [rad or m], its lines' joint
        samples (`Motion.lines`) and how the poses were solved (`Motion.solution`).

    Raises:
        InputError: A pose is out of reach, a line cannot be followed, the arm changes
            branch where the file does not allow it, the frame is unknown, or the robot's
            mounting is a gravity vector that places no base in the world; the message
            names the waypoint. An argument of the wrong type.
    """
    expect_type(robot, (Robot,), "robot", "a Robot (hdselect.load_robot)")
    expect_type(motion, (Motion,), "motion", "a Motion (hdselect.load_motion)")
    motion.check_joints(robot)
    base = robot.base_pose
    tool = motion.tool
    if tool is None:
        return _joint_motion(robot, motion)
    if base is None:
        raise InputError("the tool poses are in the world, and the mounting given as a "
                         "gravity vector does not place the base in it: use floor, wall or "
                         "ceiling, or give base = {xyz, rpy}", path=motion.path, field="mounting")
    frame = tool.frame or robot.payload_frame
    key = (str(robot.path), tuple(sorted(robot.xacro_args.items())), robot.lower.tobytes(),
           robot.upper.tobytes(), frame, base,  # a .xacro's arguments may move its links
           bool(motion.allow_flip))
    if motion.solution is not None and motion.solution.key == key:
        return motion
    try:
        kin = FrameKinematics(robot, frame)
    except InputError as err:
        field = "tool.frame" if tool.frame else "payload.frame"
        raise InputError(err.reason + ("" if tool.frame else " (the payload's frame, which "
                                       "the poses place when [tool] gives no frame)"),
                         path=motion.path, field=field) from err
    solver = _first_branch(kin, motion, tool, base)
    waypoints, lines = solver.waypoints, solver.lines
    notes = [*solver.notes, *_moved_with_robot(motion, base)]
    for note in notes:
        logger.warning("%s: %s", motion.path, note)
    solution = ToolSolution(frame, base, frozen(solver.position_error),
                            frozen(solver.orientation_error), tuple(notes), key, solver.free())
    solved = replace(motion, waypoints=frozen(waypoints), lines=tuple(lines), solution=solution,
                     warnings=_file_warnings(motion) + tuple(notes))
    return fit_lines(kin, solved, tool.tolerance) if lines else solved


def _joint_motion(robot: Robot, motion: Motion) -> Motion:
    """A motion of joint waypoints: as it is, with the note of a mounting off the floor once."""
    base = robot.base_pose
    notes = _moved_with_robot(motion, base) if len(motion.waypoints) else []
    if motion.solution is not None and motion.solution.base == base:
        return motion
    if not notes:
        return replace(motion, warnings=_file_warnings(motion), solution=None)
    for note in notes:
        logger.warning("%s: %s", motion.path, note)
    nothing = frozen(np.full(len(motion.waypoints), np.nan))
    if base is None:
        raise RuntimeError("tool poses noted for a mounting given as a gravity vector")
    return replace(motion, warnings=_file_warnings(motion) + tuple(notes), solution=ToolSolution(
        "", base, nothing, nothing, tuple(notes), ()))


def _file_warnings(motion: Motion) -> tuple[str, ...]:
    """The motion's warnings without the notes of an earlier solving (for another mounting)."""
    earlier = motion.solution.notes if motion.solution is not None else ()
    return tuple(w for w in motion.warnings if w not in earlier)


def _moved_with_robot(motion: Motion, base: BasePose | None) -> list[str]:
    """The note for joint waypoints on a robot that is not on the floor."""
    tool = motion.tool
    joints = [i for i in range(len(motion.waypoints)) if tool is None or tool.at(i) is None]
    if not joints or base is None or base == NAMED_BASES["floor"]:
        return []
    which = ("the joint waypoints" if tool is None else
             f"waypoint{'s' if len(joints) > 1 else ''} {', '.join(map(str, joints))} "
             "(joint positions)")
    keep = "keeps its" if tool is not None and len(joints) == 1 else "keep their"
    return [f"{which} {keep} joint angles on {mounting_name(base)}: the "
            "task moved with the robot; write them as tool poses (pose = {xyz, rpy}) to keep "
            "the task where it is in the world"]


def _first_branch(kin: FrameKinematics, motion: Motion, tool: ToolPoses,
                  base: BasePose) -> _Solver:
    """The motion solved from the first branch of its first pose that carries it through.

    The first waypoint's branch decides every other's. When it is a pose without a
    ``near`` hint, its solution from the middle of the joint ranges comes first, then its
    other solutions (`FIRST_SEEDS` random starts, the nearest to the middle first); the
    first from which every waypoint and line solves without a change of branch wins.

    Raises:
        InputError: No branch carries the motion through: the first branch's error.
    """
    first = tool.at(0)
    starts: list[np.ndarray | None] = [None]
    if first is not None and not first.near:
        starts += _other_solutions(kin, goal_in(base_in_world(base), first.goal(tool.approach)),
                                   tool)
    failure = None
    for start in starts:
        solver = _Solver(kin, motion, tool, base)
        try:
            solver.run(start)
            return solver
        except InputError as err:
            failure = failure or err
    if failure is None:
        raise RuntimeError("no start was tried")
    raise failure


FIRST_SEEDS = 16
"""Random starts that look for other branches of the first pose [-]."""


def _other_solutions(kin: FrameKinematics, target: Goal,
                     tolerance_of: ToolPoses) -> list[np.ndarray]:
    """Distinct solutions of a pose from random starts, the nearest to the ranges' middle first."""
    rng = np.random.default_rng(0)
    found: list[np.ndarray] = []
    lower, upper = np.maximum(kin.lower, -np.pi), np.minimum(kin.upper, np.pi)
    for _ in range(FIRST_SEEDS):
        solution = solve_pose(kin, target, rng.uniform(lower, upper),
                              tolerance=tolerance_of.tolerance)
        if solution.converged and all(np.abs(solution.q - q).max() > 0.1 for q in found):
            found.append(np.array(solution.q))
    return sorted(found, key=lambda q: float(np.abs(q - kin.middle).max()))


class _Solver:
    """The waypoints of one motion solved in order, each from the one before."""

    def __init__(self, kin: FrameKinematics, motion: Motion, tool: ToolPoses,
                 base: BasePose) -> None:
        self.kin, self.motion, self.tool, self.base = kin, motion, tool, base
        count = len(motion.waypoints)
        self.position_error = np.full(count, np.nan)
        self.orientation_error = np.full(count, np.nan)
        self.notes: list[str] = []
        self.waypoints = np.array(motion.waypoints)
        self.lines: list[LinePath] = []
        self.words = Words(kin, motion, base)

    def run(self, first: np.ndarray | None = None) -> None:
        """Every waypoint in joint positions, and the lines' samples, in order.

        Args:
            first: Joint positions that solve the first pose (its branch), or None to
                solve it from the middle of the ranges.
        """
        kin, tool = self.kin, self.tool
        waypoints, lines = self.waypoints, self.lines
        for i in range(len(waypoints)):
            written = tool.at(i)
            before = waypoints[i - 1] if i else None
            if written is None:
                if before is not None and tool.at(i - 1) is not None:
                    self._check_branch(i, before, waypoints[i], "joints")
                continue
            target = self.goal(written)
            if written.line:
                if before is None:
                    raise RuntimeError("a straight line into the first waypoint passed the reader")
                start = self._line_start(tool.at(i - 1), target, before)
                found = solve_line(kin, i, start, target, before, tool.tolerance)
                if isinstance(found, LineStop):
                    raise InputError(self.words.line_message(i, start, target, found),
                                     path=self.motion.path, field=f"waypoint[{i}].line")
                lines.append(found)
                waypoints[i] = found.q[-1]
                self.position_error[i] = found.position_error[-1]
                self.orientation_error[i] = found.orientation_error[-1]
                continue
            seed = kin.hinted(before if before is not None else
                              first if first is not None else kin.seed(), written.near)
            solution = solve_pose(kin, target, seed, tolerance=tool.tolerance,
                                  restarts=RESTARTS, rng_seed=i)
            if not solution.converged:
                raise InputError(self.words.unreachable(solution), path=self.motion.path,
                                 field=f"waypoint[{i}].pose")
            if written.near:
                solution, note = honour(kin, written, target, seed, solution,
                                        tool.tolerance, self.words, bool(self.motion.allow_flip))
                self.notes += [note] if note else []
            if before is not None and not written.near and \
                    check_branch(kin, before, solution.q).flipped:
                solution = self._on_branch(i, target, before, solution)
            waypoints[i] = solution.q
            self.position_error[i] = solution.position_error
            self.orientation_error[i] = solution.orientation_error
            if before is not None:
                self._check_branch(i, before, waypoints[i],
                                   "near" if written.near else "searched")
        self._close_cycle()

    def _close_cycle(self) -> None:
        """Close a cycle that ends at its first pose with joints whole turns away.

        Repeating it needs a turn back that it does not contain. A last waypoint written
        as a pose (not a line) takes the first's joints, with a note, if the move into it
        keeps the branch or the waypoint allows ``reconfigure``. A last pose that fixes
        less than a full pose (`Target`), met by the first's joints, takes them whenever
        the move into them keeps the branch: its free coordinates as the first's, so that
        the cycle closes in joint space.

        Raises:
            InputError: The cycle cannot be closed so; field ``waypoint[n]``, the last.
        """
        kin, tool, waypoints = self.kin, self.tool, self.waypoints
        n = len(waypoints) - 1
        turns = whole_turns(kin, waypoints[0], waypoints[n])
        last = tool.at(n)
        target = self.goal(last) if last is not None else kin.placement(waypoints[n])
        errors = goal_error(kin.placement(waypoints[0]), target)
        if isinstance(target, Target) and last is not None and not last.line and n > 1 \
                and tool.tolerance.holds(*errors) \
                and not check_branch(kin, waypoints[n - 1], waypoints[0]).flipped:
            waypoints[n] = waypoints[0]
            self.position_error[n], self.orientation_error[n] = errors
            return
        if (tool.at(0) is None and last is None) or not turns.any() \
                or not tool.tolerance.holds(*errors):
            return
        names = kin.robot.joint_names
        turned = ", ".join(f"{names[j]} {self.words.joint(j, 2 * np.pi * turns[j], signed=True)}"
                           for j in range(kin.dof) if turns[j])
        what = (f"the tool is back at waypoint[0]'s pose with {turned} from waypoint[0]'s "
                "joints: the cycle does not close in joint space, and repeating it needs a "
                "turn back that it does not contain")
        if last is None:
            advice = f"give waypoint[0] a near hint of waypoint[{n}]'s joints"
        elif last.line:
            advice = (f"add a waypoint after waypoint[{n}] at waypoint[0]'s pose with "
                      "reconfigure = true: the cycle then contains the turn back")
        else:
            check = check_branch(kin, waypoints[n - 1], waypoints[0])
            if not check.flipped or n in tool.reconfigure:
                moves = ", ".join(f"{names[j]} {self.words.joint(j, move, signed=True)}" for j, move
                                  in enumerate(waypoints[0] - waypoints[n - 1]) if turns[j])
                waypoints[n] = waypoints[0]
                self.position_error[n], self.orientation_error[n] = errors
                self.notes.append(
                    f"waypoint[{n}]: {what}; it takes waypoint[0]'s joints instead, so the "
                    f"move from waypoint[{n - 1}] turns {moves}" + (
                        f" ({'; '.join(check.reasons)}); allowed by waypoint[{n}].reconfigure"
                        if check.flipped else ""))
                return
            advice = (f"returning to waypoint[0]'s joints from waypoint[{n - 1}] changes "
                      f"branch ({'; '.join(check.reasons)}): allow it with reconfigure = true "
                      f"on waypoint[{n}], and the cycle contains the turn back")
        raise InputError(f"{what}; {advice}", path=self.motion.path, field=f"waypoint[{n}]")

    def goal(self, written: PoseWaypoint) -> Goal:
        """What a pose waypoint asks of the tool, in the base frame."""
        return goal_in(base_in_world(self.base), written.goal(self.tool.approach))

    def _line_start(self, previous: PoseWaypoint | None, end: Goal, before: np.ndarray) -> Goal:
        """Where a line into `end` starts: the pose before it, as `end` asks for one.

        A full pose's line starts at the pose written before it, else at the tool as the
        waypoint before put it; a target's at the target before it, where that is of the
        same kind, else at what the tool as put before has of `end`'s kind.
        """
        placement = self.kin.placement(before)
        if isinstance(end, Target):
            if previous is not None and previous.kind == end.kind:
                return self.goal(previous)
            return end.like(placement)
        if previous is not None and previous.rpy is not None:
            return in_base(self.base, previous.pose)
        return placement

    def free(self) -> tuple[tuple[tuple[str, float], ...], ...]:
        """Per waypoint, the coordinates its pose leaves free, as solved (`Target.free`)."""
        out = []
        for i, q in enumerate(self.waypoints):
            written = self.tool.at(i)
            goal = self.goal(written) if written is not None else None
            out.append(goal.free(self.kin.placement(q)) if isinstance(goal, Target) else ())
        return tuple(out)

    def _on_branch(self, i: int, target: Goal, before: np.ndarray,
                   found: PoseSolution) -> PoseSolution:
        """A solution on the branch of `before`, if other seeds find one; else `found`.

        Of the solutions that keep the branch, the one with the smallest joint move wins.
        """
        kin, rng = self.kin, np.random.default_rng(1000 + i)
        best, smallest = found, np.inf
        for k in range(BRANCH_SEEDS):
            spread = (0.2, 0.5, 1.0)[k % 3]
            seed = (before + rng.normal(0.0, spread, kin.dof) if k < BRANCH_SEEDS // 2
                    else rng.uniform(np.maximum(kin.lower, -np.pi), np.minimum(kin.upper, np.pi)))
            other = solve_pose(kin, target, seed, tolerance=self.tool.tolerance)
            if not other.converged:
                continue
            check = check_branch(kin, before, other.q)
            if not check.flipped and check.joint_move < smallest:
                best, smallest = other, check.joint_move
        return best

    def _check_branch(self, i: int, before: np.ndarray, after: np.ndarray, how: str) -> None:
        """Refuse a change of branch into waypoint `i`, unless it says ``reconfigure``.

        `how` says how waypoint `i` got its joints: ``"joints"`` (given), ``"near"`` (solved
        from its hint) or ``"searched"`` (solved, no same-branch solution found).
        """
        check = check_branch(self.kin, before, after)
        if not check.flipped:
            return
        names = self.kin.robot.joint_names
        moved = np.argsort(-np.abs(after - before))[:3]
        moves = ", ".join(f"{names[j]} {self.words.joint(j, after[j] - before[j], signed=True)}"
                          for j in moved if abs(after[j] - before[j]) > 1e-6)
        what = (f"the arm changes branch between waypoint[{i - 1}] and waypoint[{i}]: "
                f"{'; '.join(check.reasons)} ({moves})")
        if i in self.tool.reconfigure:
            self.notes.append(f"{what}; allowed by waypoint[{i}].reconfigure")
            return
        if how == "joints":
            hint = ", ".join(f"{names[j]} = {self.words.number(j, after[j])}" for j in moved)
            advice = (f"waypoint[{i - 1}]'s pose was solved on another branch than waypoint"
                      f"[{i}]'s joints: give waypoint[{i - 1}] a hint such as near = {{{hint}}}")
        elif how == "near":
            advice = f"waypoint[{i}]'s near chose the other branch: change it"
        else:
            advice = (f"no solution on waypoint[{i - 1}]'s branch was found from "
                      f"{BRANCH_SEEDS + 1} starts: move the pose, or give waypoint[{i}] a near "
                      "hint of the joints it should have")
        raise InputError(f"{what}; {advice}, or allow the change with reconfigure = true",
                         path=self.motion.path, field=f"waypoint[{i}]")
