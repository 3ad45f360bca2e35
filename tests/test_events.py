"""Payload events: which samples carry which part (hdselect.motion.events)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from hdselect import InputError
from hdselect.motion.events import Event, carried
from hdselect.motion.motionfile import load_motion
from hdselect.motion.planning import plan
from hdselect.robot.model import load_robot
from helpers import REPO

ROBOT = REPO / "robots" / "index_table.urdf"

PARTS = """
[payloads.part]
mass = 0.8
com = [0.11, 0.0, 0.05]
frame = "disk"

[payloads.tray]
mass = 0.3
frame = "disk"
"""


def motion_file(folder: Path, waypoints: list[dict[str, object]], extra: str = PARTS) -> Path:
    """An index-table motion through `waypoints` (each a dict of q, dwell, attach, release)."""
    lines = [f'robot = "{ROBOT}"', 'planner = "ruckig"', 'angle_unit = "deg"', "dt = 0.001",
             extra, "[limits]", "velocity = 300", "acceleration = 1500", "jerk = 30000"]
    for point in waypoints:
        lines.append("[[waypoint]]")
        for key, value in point.items():
            lines.append(f"{key} = {value!r}".replace("'", '"'))
    path = folder / "events.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def planned(path: Path):
    motion = load_motion(path, ROBOT)
    return motion, plan(load_robot(ROBOT), motion)


def expected(motion, trajectory, attach: int, release: int) -> np.ndarray:
    """The mask by the stated rule: arrival at `attach` to the end of `release`'s dwell."""
    t = np.minimum(trajectory.t, trajectory.duration)
    start = trajectory.waypoint_times[attach]
    end = trajectory.waypoint_times[release] + motion.dwells[release]
    tol = 1e-6 * trajectory.dt
    after, before = t >= start - tol, t <= end + tol
    return (after & before) if attach < release else (after | before)


def test_carried_from_arrival_at_attach_to_end_of_release_dwell(tmp_path):
    path = motion_file(tmp_path, [{"q": [0], "dwell": 0.3}, {"q": [90], "dwell": 0.5,
                                  "attach": "part"}, {"q": [180], "dwell": 0.4},
                                  {"q": [270], "dwell": 0.6, "release": "part"},
                                  {"q": [360], "dwell": 0.2}])
    motion, trajectory = planned(path)
    assert motion.events == (Event("part", True, 1), Event("part", False, 3))
    found = carried(motion, trajectory)
    assert [p.name for p in found.parts] == ["part"]
    mask = found.mask[:, 0]
    np.testing.assert_array_equal(mask, expected(motion, trajectory, 1, 3))
    # the boundaries: the first sample of the attach waypoint's arrival and the last of
    # the release waypoint's dwell carry it; the samples just outside do not
    times = trajectory.waypoint_times
    first = int(np.round(times[1] / trajectory.dt))
    last = int(np.round((times[3] + motion.dwells[3]) / trajectory.dt))
    assert mask[first] and not mask[first - 1] and mask[last] and not mask[last + 1]
    assert np.all(mask[first:last + 1]) and np.count_nonzero(mask) == last - first + 1
    assert found.events == ((pytest.approx(times[1]), "part", True),
                            (pytest.approx(times[3] + 0.6), "part", False))
    # whole dwells carry it: the attach waypoint's and the release waypoint's
    assert found.names(first) == ("part",) and found.names(0) == ()
    states = found.states()
    assert [state for state, _ in states] == [(), (0,)]
    rows = np.sort(np.concatenate([r for _, r in states]))
    np.testing.assert_array_equal(rows, np.arange(len(trajectory.t)))
    np.testing.assert_array_equal(states[1][1], np.flatnonzero(mask))
    assert not found.mask.flags.writeable
    # the tray no event names rides the whole cycle on the robot, not in the events
    assert set(motion.parts) == {"part", "tray"}


def test_a_release_before_the_attach_wraps_around_the_cycle(tmp_path):
    path = motion_file(tmp_path, [{"q": [0], "dwell": 0.3}, {"q": [90], "dwell": 0.5,
                                  "release": "part"}, {"q": [180], "dwell": 0.4},
                                  {"q": [270], "dwell": 0.6, "attach": "part"},
                                  {"q": [360], "dwell": 0.2}])
    motion, trajectory = planned(path)
    found = carried(motion, trajectory)
    mask = found.mask[:, 0]
    np.testing.assert_array_equal(mask, expected(motion, trajectory, 3, 1))
    assert mask[0] and mask[-1] and not mask[len(mask) // 2]


def test_several_parts_and_the_payload_give_one_state_per_carried_set(tmp_path):
    extra = PARTS + "\n[payload]\nmass = 0.2\nframe = \"disk\"\n"
    path = motion_file(tmp_path, [{"q": [0], "dwell": 0.3, "attach": ["part", "payload"]},
                                  {"q": [90], "dwell": 0.5, "release": "part"},
                                  {"q": [180], "dwell": 0.4, "attach": "tray"},
                                  {"q": [270], "dwell": 0.6, "release": ["tray", "payload"]},
                                  {"q": [360], "dwell": 0.2}], extra)
    motion, trajectory = planned(path)
    found = carried(motion, trajectory)
    assert [p.name for p in found.parts] == ["part", "payload", "tray"]
    assert found.parts[1].mass == 0.2
    for i, (attach, release) in enumerate([(0, 1), (0, 3), (2, 3)]):
        np.testing.assert_array_equal(found.mask[:, i],
                                      expected(motion, trajectory, attach, release))
    sets = [state for state, _ in found.states()]
    assert sets == [(0, 1), (1,), (1, 2), ()]


def test_a_motion_without_events_carries_nothing_by_events(tmp_path):
    path = motion_file(tmp_path, [{"q": [0], "dwell": 0.3}, {"q": [90]}])
    motion, trajectory = planned(path)
    assert motion.events == () and carried(motion, trajectory) is None


@pytest.mark.parametrize(("points", "field", "words"), [
    ([{"attach": "part"}, {"attach": "part"}, {"release": "part"}], "waypoint[1].attach",
     "attached again"),
    ([{"attach": "part"}, {"release": "part"}, {"release": "part"}], "waypoint[2].release",
     "released again"),
    ([{"attach": "part"}, {"release": "part"}, {"attach": "part"}], "waypoint[0].attach",
     "the cycle repeats"),
    ([{"attach": "part"}, {}, {}], "waypoint[0].attach", "never released"),
    ([{"release": "part"}, {}, {}], "waypoint[0].release", "never attached"),
    ([{"attach": "part", "release": "part"}, {}, {}], "waypoint[0].release", "both"),
    ([{"attach": "bolt"}, {}, {}], "waypoint[0].attach", "unknown part 'bolt'"),
    ([{"attach": 3}, {}, {}], "waypoint[0].attach", "a part's name"),
    ([{"attach": []}, {}, {}], "waypoint[0].attach", "a part's name"),
    ([{"attach": ["part", "part"]}, {"release": "part"}, {}], "waypoint[0].attach", "twice"),
    ([{"attach": "payload"}, {"release": "payload"}, {}], "waypoint[0].attach",
     "unknown part 'payload'"),
])
def test_events_that_do_not_alternate_or_name_no_part_are_refused(tmp_path, points, field,
                                                                   words):
    path = motion_file(tmp_path, [{"q": [90 * i], "dwell": 0.2, **p}
                                  for i, p in enumerate(points)])
    with pytest.raises(InputError) as err:
        load_motion(path, ROBOT)
    assert err.value.field == field and words in err.value.reason
    assert "\n" not in str(err.value)
