"""The whole force and moment through each joint along a trajectory, in batches.

After `pinocchio.rnea`, ``data.f[i]`` is the wrench the parent side applies to the
child side through joint i (gravity included), in joint i's frame after its motion,
the moment about that frame's origin, stacked ``(force [N]; moment [N m])``. Its
axis component is the joint torque; the rest loads the joint's output bearing.

`joint_wrenches` computes the same wrenches for a whole batch of states with a
recursive Newton-Euler pass in numpy that loops over joints, never over samples
(Pinocchio's recursion, rnea.hxx):

    v_i = X_i v_parent + S qd_i
    a_i = X_i a_parent + S qdd_i + v_i x S qd_i        (a_base = -g)
    f_i = I_i a_i + v_i x* I_i v_i + sum over children c of X_c^T f_c

Each joint frame is first turned, once, by a constant rotation whose z axis is the
joint axis: every joint is then a turn about z or a slide along z, so the per-sample
part of a transform is a plane rotation (or a shift) and the rest one constant 6x6
product over a block of samples. `axis_wrenches` gives the wrenches in those axis
frames, where the axial force, the radial force and the tilting moment are rows
(`bearing_loads`). Pinocchio's armature is the rotor's and is in no wrench.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from hdselect.robot.dynamics import distinct_states
from hdselect.robot.joint_motions import JointMotion, joint_motions
from hdselect.robot.model import Robot

BLOCK = 10_000
"""Most samples per block. A (6, BLOCK) array is 0.5 MB, so a joint's work stays in cache,
and the 6x6 by (6, BLOCK) products stay below the size at which OpenBLAS starts threads of
its own (32768 columns cost 10x here). Not a power of two: rows 2^k bytes apart share
cache sets (8192 was 10 % slower than 10000)."""


def joint_wrenches(robot: Robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, *,
                   threads: int | None = None) -> np.ndarray:
    """Every joint's transmitted wrench along a batch of states, as ``data.f`` after rnea.

    Args:
        robot: The robot (payload and gearhead masses included).
        q: Joint positions [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof).
        qdd: Joint accelerations [rad/s^2 or m/s^2], shape (n, dof).
        threads: Threads sharing the blocks; None chooses from the sample count.

    Returns:
        Wrenches, shape (n_joints, 6, n), joints in the model's order (mimic followers
        included): the force [N] then the moment about the joint origin [N m] that the
        parent side applies to the child side, in the joint frame.
    """
    rnea = _Rnea(robot)
    distinct = distinct_states(q, qd, qdd)
    if distinct is None:
        return rnea.run(q, qd, qdd, range(len(rnea.joints)), aligned=False, threads=threads)
    once, index = distinct
    return rnea.run(q[once], qd[once], qdd[once], range(len(rnea.joints)), aligned=False,
                    threads=threads)[:, :, index]


def axis_wrenches(robot: Robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                  joints: Sequence[str], *, threads: int | None = None) -> np.ndarray:
    """The named joints' transmitted wrenches in their axis frames, along a batch of states.

    A joint's axis frame has its origin at the joint origin and its z axis along the
    joint axis as the robot file gives it (x and y complete it, turning with the
    child link). So rows (0, 1) are the radial force, row 2 the axial force, rows
    (3, 4) the tilting moment about the origin and row 5 the torque.

    Args:
        robot: The robot (payload and gearhead masses included).
        q: Joint positions [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof).
        qdd: Joint accelerations [rad/s^2 or m/s^2], shape (n, dof).
        joints: The joints wanted, by name.
        threads: Threads sharing the blocks; None chooses from the sample count.

    Returns:
        Wrenches [N, N m], shape (len(joints), 6, n).
    """
    rows, index = distinct_axis_wrenches(robot, q, qd, qdd, joints, threads=threads)
    return rows if index is None else rows[:, :, index]


def distinct_axis_wrenches(robot: Robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                           joints: Sequence[str], *, threads: int | None = None,
                           distinct: tuple[np.ndarray, np.ndarray] | None | bool = True
                           ) -> tuple[np.ndarray, np.ndarray | None]:
    """`axis_wrenches`, a state repeated by the samples after it (a dwell) given once.

    Args:
        robot: The robot (payload and gearhead masses included).
        q: Joint positions [rad or m], shape (n, dof).
        qd: Joint velocities [rad/s or m/s], shape (n, dof).
        qdd: Joint accelerations [rad/s^2 or m/s^2], shape (n, dof).
        joints: The joints wanted, by name.
        threads: Threads sharing the blocks; None chooses from the sample count.
        distinct: These states' `hdselect.robot.dynamics.distinct_states`, when already
            known (None: every sample its own); True finds them.

    Returns:
        The wrenches of the distinct states [N, N m], (len(joints), 6, m), and the row of
        each sample among them, (n,); None when every sample has its own row.
    """
    model = robot.model
    keep = [model.getJointId(name) - 1 for name in joints]
    rnea = _Rnea(robot)
    if distinct is True:
        distinct = distinct_states(q, qd, qdd)
    if distinct is None or distinct is False:
        return rnea.run(q, qd, qdd, keep, aligned=True, threads=threads), None
    once, index = distinct
    return rnea.run(q[once], qd[once], qdd[once], keep, aligned=True, threads=threads), index


def bearing_loads(wrench: np.ndarray, offset: float = 0.0,
                  spread: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Axial force, radial force and tilting moment on a bearing centred on the joint axis.

    The centre is the joint origin moved `offset` along the axis; about it the moment
    is ``m - offset e_z x f``. With a `spread`, the centre is `offset` + `spread` or
    `offset` - `spread`, whichever tilts more at each sample (a bearing known to sit
    `spread` from a point on the axis, on a side not known).

    Args:
        wrench: One joint's wrench in its axis frame (`axis_wrenches`), shape (6, n) or
            its first five rows [N, N m].
        offset: The centre along the axis from the joint origin [m].
        spread: The distance of the centre from there, either way [m], >= 0.

    Returns:
        F_a, the force along the axis (signed) [N]; F_r [N] and M [N m], each (n,).
    """
    fx, fy, axial, mx, my = wrench[:5]
    radial = np.sqrt(fx * fx + fy * fy)  # np.hypot is several times slower (libm)
    tilting = _tilt(fx, fy, mx, my, offset + spread)
    if spread:
        np.maximum(tilting, _tilt(fx, fy, mx, my, offset - spread), out=tilting)
    return axial, radial, tilting


def _tilt(fx: np.ndarray, fy: np.ndarray, mx: np.ndarray, my: np.ndarray,
          offset: float) -> np.ndarray:
    """|m - offset e_z x f| in the plane normal to the axis [N m]."""
    if offset == 0.0:
        return np.sqrt(mx * mx + my * my)
    x, y = mx + offset * fy, my - offset * fx
    return np.sqrt(x * x + y * y)


def axis_turns(robot: Robot, joints: Sequence[str],
               motions: Sequence[JointMotion] | None = None) -> np.ndarray:
    """Each named joint's axis frame in its joint frame: the rotations `axis_wrenches` uses.

    Args:
        robot: The robot.
        joints: The joints, by name.
        motions: The robot's `joint_motions`, when already read.

    Returns:
        Rotations whose third column is the joint axis, shape (len(joints), 3, 3) [-].
    """
    by_name = {joint.name: joint for joint in motions or joint_motions(robot.model, robot.path)}
    return np.array([_to_z(by_name[name].axis) for name in joints]).reshape(-1, 3, 3)


def _skew(p: np.ndarray) -> np.ndarray:
    """The matrix of ``p x``."""
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def _to_z(axis: np.ndarray) -> np.ndarray:
    """A rotation whose third column is `axis` (a unit vector)."""
    helper = np.eye(3)[np.argmin(np.abs(axis))]
    x = np.cross(helper, axis)
    x /= np.linalg.norm(x)
    return np.column_stack((x, np.cross(axis, x), axis))


def _blocks(rotation: np.ndarray) -> np.ndarray:
    """The 6x6 block-diagonal matrix that turns a spatial vector by `rotation`."""
    out = np.zeros((6, 6))
    out[:3, :3] = out[3:, 3:] = rotation
    return out


class _Rnea:
    """Recursive Newton-Euler over blocks of samples, in the joints' axis frames."""

    def __init__(self, robot: Robot) -> None:
        """Express placements and inertias in the axis frames (about 0.5 ms for 6 joints)."""
        model = robot.model
        self.robot = robot
        self.joints: tuple[JointMotion, ...] = joint_motions(model, robot.path)
        self.parents = [int(model.parents[i]) - 1 for i in range(1, model.njoints)]
        turns = [_to_z(joint.axis) for joint in self.joints]
        self._force_out: list[np.ndarray] = []  # child force before q -> parent axis frame
        self._motion_in: list[np.ndarray] = []  # parent motion -> joint axis frame before q
        self._inertia: list[np.ndarray] = []
        self._turn_back = [_blocks(turn) for turn in turns]
        for k in range(len(self.joints)):
            placement = model.jointPlacements[k + 1]
            parent = turns[self.parents[k]] if self.parents[k] >= 0 else np.eye(3)
            rotation = parent.T @ placement.rotation @ turns[k]
            act = _blocks(rotation)  # an SE3 acting on a force: (f, n) -> (R f, R n + p x R f)
            act[3:, :3] = _skew(parent.T @ placement.translation) @ rotation
            self._force_out.append(act)
            self._motion_in.append(act.T)  # its inverse acting on a motion is its transpose
            spatial = np.asarray(model.inertias[k + 1].matrix())
            self._inertia.append(_blocks(turns[k]).T @ spatial @ _blocks(turns[k]))
        self._base = np.concatenate((-np.asarray(model.gravity.linear, dtype=float),
                                     np.zeros(3)))[:, None]

    def run(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, keep: Sequence[int], *,
            aligned: bool, threads: int | None) -> np.ndarray:
        """The kept joints' wrenches over every sample given, in blocks shared by the threads."""
        n = q.shape[0]
        config = self.robot.configuration(q)
        velocity, acceleration = np.ascontiguousarray(qd.T), np.ascontiguousarray(qdd.T)
        keep = list(keep)
        out = np.empty((len(keep), 6, n))
        count = -(-n // BLOCK)
        size = -(-n // count) if n else 1  # equal blocks, none longer than BLOCK
        starts = range(0, n, size)

        def block(start: int) -> None:
            cols = slice(start, min(start + size, n))
            self._block(config[:, cols], velocity[:, cols], acceleration[:, cols], keep,
                        aligned, out[:, :, cols])

        if threads is None:
            threads = min(os.cpu_count() or 1, len(starts))
        if threads <= 1 or len(starts) <= 1:
            for start in starts:
                block(start)
        else:
            with ThreadPoolExecutor(min(threads, len(starts))) as pool:
                list(pool.map(block, starts))
        return out

    def _block(self, q: np.ndarray, v: np.ndarray, a: np.ndarray, keep: list[int],
               aligned: bool, out: np.ndarray) -> None:
        """One block of k samples: fill `out` (len(keep), 6, k) [N, N m]."""
        k = q.shape[1]
        velocity: list[np.ndarray] = []
        acceleration: list[np.ndarray] = []
        force: list[np.ndarray] = []
        turns: list[tuple[np.ndarray, ...]] = []
        for j, joint in enumerate(self.joints):
            rate, accel = v[joint.v_index], a[joint.v_index]
            if joint.scaling != 1.0:
                rate, accel = joint.scaling * rate, joint.scaling * accel
            if joint.unbounded:  # (sin, cos) as Pinocchio uses them
                turn: tuple[np.ndarray, ...] = (q[joint.q_index + 1], q[joint.q_index])
            elif joint.revolute:
                angle = joint.coordinate(q)
                turn = (np.sin(angle), np.cos(angle))
            else:
                turn = (joint.coordinate(q),)
            turns.append(turn)
            p = self.parents[j]
            if p < 0:  # the fixed base, accelerating at -g
                vel = np.zeros((6, k))
                acc = np.empty((6, k))
                acc[:] = self._motion_in[j] @ self._base
            else:
                vel = self._motion_in[j] @ velocity[p]
                acc = self._motion_in[j] @ acceleration[p]
                _motion_into_child(vel, turn)
            _motion_into_child(acc, turn)
            # the joint's own motion S qd, its bias v x S qd, and S qdd (S along e_z)
            if joint.revolute:
                vel[5] += rate
                acc[0] += vel[1] * rate
                acc[1] -= vel[0] * rate
                acc[3] += vel[4] * rate
                acc[4] -= vel[3] * rate
                acc[5] += accel
            else:
                vel[2] += rate
                acc[0] += vel[4] * rate
                acc[1] -= vel[3] * rate
                acc[2] += accel
            velocity.append(vel)
            acceleration.append(acc)
            momentum = self._inertia[j] @ vel
            f = self._inertia[j] @ acc
            _add_cross(vel[3:], momentum[:3], f[:3])  # v x* h = (w x h_f, w x h_n + v x h_f)
            _add_cross(vel[3:], momentum[3:], f[3:])
            _add_cross(vel[:3], momentum[:3], f[3:])
            force.append(f)
        rows = {j: r for r, j in enumerate(keep)}
        for j in reversed(range(len(self.joints))):
            f = force[j]
            if j in rows:
                if aligned:
                    out[rows[j]] = f
                else:
                    np.matmul(self._turn_back[j], f, out=out[rows[j]])
            p = self.parents[j]
            if p >= 0:
                _force_out_of_child(f, turns[j])
                force[p] += self._force_out[j] @ f


def _add_cross(a: np.ndarray, b: np.ndarray, out: np.ndarray) -> None:
    """``out += a x b`` column by column, for (3, k) arrays."""
    out[0] += a[1] * b[2]
    out[0] -= a[2] * b[1]
    out[1] += a[2] * b[0]
    out[1] -= a[0] * b[2]
    out[2] += a[0] * b[1]
    out[2] -= a[1] * b[0]


def _motion_into_child(motion: np.ndarray, turn: tuple[np.ndarray, ...]) -> None:
    """A spatial motion (6, k) in the axis frame before q, expressed after it, in place.

    A turn by q about z turns both halves by Rz(q)^T; a slide q along z moves the
    reference point by q e_z (linear += angular x q e_z).
    """
    if len(turn) == 2:
        sin, cos = turn
        for x, y in ((0, 1), (3, 4)):
            old = motion[x].copy()
            motion[x] *= cos
            motion[x] += sin * motion[y]
            motion[y] *= cos
            motion[y] -= sin * old
    else:
        (lift,) = turn
        motion[0] += motion[4] * lift
        motion[1] -= motion[3] * lift


def _force_out_of_child(force: np.ndarray, turn: tuple[np.ndarray, ...]) -> None:
    """A spatial force (6, k) in the axis frame after q, expressed before it, in place.

    Rz(q) on both halves for a turn; for a slide the moment is taken about the origin
    q e_z below (n += q e_z x f).
    """
    if len(turn) == 2:
        sin, cos = turn
        for x, y in ((0, 1), (3, 4)):
            old = force[x].copy()
            force[x] *= cos
            force[x] -= sin * force[y]
            force[y] *= cos
            force[y] += sin * old
    else:
        (lift,) = turn
        force[3] -= lift * force[1]
        force[4] += lift * force[0]

