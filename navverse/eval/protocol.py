"""The observation protocol: what an agent may be told and see in each task, and the track it runs in.

A benchmark number means something only if every entry saw the same things. The runner
(``navverse run-agent``) enforces this table for an agent that is not ``privileged``:

=========  ===============================================  ===========================================
task       ``goal`` (text) and ``goal_id``                  ``AgentTask.goal_category``
=========  ===============================================  ===========================================
ObjNav     the object category; its id                      the category
PlaceNav   the instruction of the run's type (``category``  the place category under ``category``;
           names the place, ``route`` describes the way,    "" under ``route`` and ``intention``
           ``intention`` states a need); the id only under
           ``category``, else -1
VLN        the instruction only; -1                         "" (the instruction is the whole task)
=========  ===============================================  ===========================================

**Sensors.** An agent lists the camera images it looks at (``sensors``); ``rgb`` and ``depth`` are
the standard sensors and the default (:data:`DEFAULT_SENSORS`). ``semantic`` (the simulator's
ground-truth instance ids) is opt-in, and only an agent that asks for it is told which category each
instance id is (``AgentTask.semantic_categories``); otherwise it gets an empty map.

**Privileged agents** (``privileged = True``: the oracle, ``gt_goal``) are baselines, not entries:
they are told the category and the instance map whatever the task, and ``info`` carries the goal
positions and the reference path.

**Tracks.** Every submission the runner writes records its track on each line
(``{"name", "sensors", "privileged"}``): ``standard`` (rgb and/or depth, not privileged),
``gt-semantic`` (uses the ground-truth semantic sensor) or ``privileged``. The evaluator reads it
(:func:`submission_track`), prints it, and puts it in ``metrics.json``, the tables and the report, so
that results of different tracks are not compared unawares. A submission written by other means
without a track is ``unspecified``.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

__all__ = [
    "DEFAULT_SENSORS",
    "HIDDEN_CATEGORY_TYPES",
    "SENSOR_NAMES",
    "STANDARD_SENSORS",
    "TRACK_NAMES",
    "UNSPECIFIED",
    "agent_sensors",
    "check_track",
    "describe",
    "is_told_category",
    "track_of",
]

SENSOR_NAMES = ("rgb", "depth", "semantic")
"""The camera images an agent may look at (those :data:`navverse.env.SENSORS` renders)."""
STANDARD_SENSORS = ("rgb", "depth")
"""Sensors of the standard track."""
DEFAULT_SENSORS = STANDARD_SENSORS
"""The sensors of an agent that does not list its own."""
HIDDEN_CATEGORY_TYPES = frozenset({"route", "intention"})
"""PlaceNav instruction types under which an agent that is not privileged is not told the category."""
TRACK_NAMES = ("standard", "gt-semantic", "privileged")
"""The tracks, from the least to the most an agent is given."""
UNSPECIFIED = {"name": "unspecified", "sensors": None, "privileged": None}
"""The track of a submission that does not record one."""


def agent_sensors(agent: object) -> tuple[str, ...]:
    """The camera images an agent looks at: its ``sensors``, else :data:`DEFAULT_SENSORS`."""
    sensors = getattr(agent, "sensors", None)
    return DEFAULT_SENSORS if sensors is None else tuple(sensors)


def track_of(sensors: Iterable[str], *, privileged: bool) -> dict:
    """The track of an agent with these sensors: ``{"name", "sensors", "privileged"}``."""
    chosen = sorted(set(sensors))
    if privileged:
        name = "privileged"
    elif "semantic" in chosen:
        name = "gt-semantic"
    else:
        name = "standard"
    return {"name": name, "sensors": chosen, "privileged": bool(privileged)}


def is_told_category(task: str, instruction_type: str | None, *, privileged: bool) -> bool:
    """Whether an agent is told the category it seeks (``AgentTask.goal_category``), by the table of
    the module docstring."""
    if privileged:
        return True
    if task == "vln":
        return False
    return not (task == "placenav" and instruction_type in HIDDEN_CATEGORY_TYPES)


def describe(track: dict) -> str:
    """One line naming a track, for tables and reports: ``standard (depth, rgb)``."""
    sensors: Sequence[str] | None = track.get("sensors")
    if sensors is None:
        return str(track.get("name", "unspecified"))
    return f"{track['name']} ({', '.join(sensors) or 'no camera'})"


def check_track(value: object) -> tuple[dict | None, str | None]:
    """A submission record's ``track`` (None when absent), or why it is not one: an object with
    ``name`` (one of :data:`TRACK_NAMES`), ``sensors`` (names of :data:`SENSOR_NAMES`) and
    ``privileged`` (true or false) that agree with each other (:func:`track_of`)."""
    if value is None:
        return None, None
    if not isinstance(value, dict) or set(value) != {"name", "sensors", "privileged"}:
        return None, 'track must be {"name": ..., "sensors": [...], "privileged": true|false} or null'
    sensors, privileged = value["sensors"], value["privileged"]
    if not isinstance(sensors, list) or not all(isinstance(x, str) and x in SENSOR_NAMES for x in sensors):
        return None, f"track sensors must be a list of {', '.join(SENSOR_NAMES)}"
    if not isinstance(privileged, bool):
        return None, "track privileged must be true or false"
    expected = track_of(sensors, privileged=privileged)
    if value["name"] != expected["name"]:
        return None, (
            f"track name must be {expected['name']!r} for sensors {sorted(sensors)} and privileged "
            f"{str(privileged).lower()}, not {str(value['name'])[:40]!r} (names: {', '.join(TRACK_NAMES)})"
        )
    return expected, None
