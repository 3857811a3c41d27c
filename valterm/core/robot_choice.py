"""Which robots ``--robot`` (and a task file's ``robot`` key) can name: the thesis's own model,
the default, and the bundled robot files with a DH table (core/arms.py makes their arms).

Without numpy: the command line checks ``--robot`` and the status line names the robot
before the kinematics load (issue 25, the start).
"""

from __future__ import annotations

from functools import lru_cache

from valterm.core import resources
from valterm.core.errors import RefusedValue

THESIS_ROBOT = "PUMA"  # the thesis's own model (robot/PUMA.toml), the default robot
ROBOT_FOLDER = "robot"  # the bundled robot files


def robot_names() -> list[str]:
    """The robots a user can choose with --robot: the bundled robot files with a DH table."""
    return list(_bundled_dh_robots())


@lru_cache(maxsize=1)
def _bundled_dh_robots() -> tuple[str, ...]:
    # read once: the command line's --robot help asks at every start, the bundle never changes
    folder = resources.data_path(ROBOT_FOLDER)
    return tuple(sorted(p.stem for p in folder.glob("*.toml") if "[dh]" in p.read_text(encoding="utf-8")))


def robot_keys() -> list[str]:
    """What --robot takes: the thesis's robot first, then the bundled DH robot files."""
    return [THESIS_ROBOT, *robot_names()]


def check_robot(name: str) -> str:
    """The robot's name as --robot and a task file spell it (PUMA560), or RefusedValue."""
    key = name.strip().upper()
    if key not in robot_keys():
        raise RefusedValue(f"no robot {key!r}; the robots are {THESIS_ROBOT} (the thesis's, the default), "
                           f"{', '.join(robot_names())}")
    return key
