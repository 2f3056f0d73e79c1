"""The paper's metrics (Appendix A.5) and termination labels (A.6): their definitions, and the registry.

Scoring has two layers:

1. :func:`navverse.eval.measures.measure` turns trajectories into per-episode **measures**, computing
   over all rows of a batch of episodes at once (no Python loop over rows): distance to goal at the
   start, end and closest point, 3-D path length, duration, visited 1 m cells, collision, mean
   obstacle distance, share of rows on preferred surfaces, fall and timeout, nDTW for VLN, and the exit
   measures for indoor-to-outdoor episodes.
2. **Metrics** are registered here with :func:`metric` and the names they need (measures, episode
   facts or other metrics); :func:`compute_metrics` resolves that graph and evaluates each metric once,
   over arrays of episodes.

Definitions (``p_t`` the base position, ``T`` the last row, ``r`` = r_robot, tolerance ``1.0 + r``):

* ``d_t = max(0, ||p_t - p_goal||_2 - r_goal)`` in 3-D to the nearest goal instance; DTG = ``d_T``.
* Rows after 300 s are not scored (the episode timed out there); rows after the first whose tilt
  (angle between the base's z axis and the world's, from the quaternion) exceeds 45° are not scored
  (the robot fell there).
* Label: ``fall`` if it fell; else ``success`` if ``d_T <= 1.0 + r`` (the paper's criterion: final
  distance; stop is not required); else ``wrong_goal`` if it called stop; else ``timeout`` (it neither
  stopped nor reached the goal within its time: past 300 s, or ended by its simulator).
* SR = success; SPL = success · L / max(L, P) with L the dataset's geodesic distance and P the 3-D
  path length (L = P = 0 gives 1); SS = max(0, 1 − d_T / d_0) (d_0 = 0 gives 1 if d_T = 0, else 0);
  SoftSPL = SS · L / max(L, P); NE = d_T; OS = [min_t d_t <= 1.0 + r]; CE = |cells| / max(P, 1 m),
  cells the 1 m grid cells the path passes through (rows farther apart than 0.25 m are subdivided);
  CR = [any collision]; ADO = mean over rows of the obstacle distance at the base
  (:mod:`navverse.scene.fields`); NSR = mean over rows of [the surface under the base is preferred by
  the embodiment]; speed = P / duration.
* Collisions: the submission's ``collisions`` times when given (a simulator's non-ground contacts,
  counted up to the last scored row); otherwise the robot's footprint, a capsule of the body's width
  along its length, is checked against the scene's obstacle field at every row.
* nDTW = exp(−DTW(Q, R) / (|R| · d_th)) with d_th the success distance, Q and R the trajectory and
  the reference path resampled every 0.5 m in the horizontal plane; SDTW = success · nDTW (VLN).
* Transition (the paper's stage-wise analysis; only episodes of ``i2o`` scenes with an indoor region,
  undefined for every other episode): the **exit row** ``k`` is the first scored row whose base lies
  outside the indoor region (the ``indoor`` field of :mod:`navverse.scene.fields`). Ind-Only = [no such
  row]; Reach-Out = [there is one] (= 1 − Ind-Only). The path splits at ``k``: rows ``0..k`` are before
  the exit (all rows if it never exits), rows ``k..T`` after it (the exit row is in both, so the two
  lengths add up to P). CE before / after the exit = |cells| / max(P, 1 m) of each part, with the
  cells of CE; CE before is undefined when the robot starts outdoors (``k = 0``), CE after when it never
  exits. Post-exit failure causes: over the failed episodes that reached outdoors, [label is wrong
  goal], [fall], [timeout] (undefined for every other episode, so their means are the shares).

Episodes without a valid trajectory (missing from a submission or invalid) are failures: their SR,
SPL, SS, SoftSPL and OS are 0 and their trajectory measures undefined (NaN, left out of those means).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from navverse.eval.measures import TRANSITION_SCENE_TYPES

__all__ = ["LABELS", "METRICS", "Metric", "compute_metrics", "metric"]

CE_EPSILON = 1.0
"""``max(P, ε)`` in CE (m): a robot that does not move covers its own cell per meter."""
LABELS = ("success", "wrong_goal", "fall", "timeout", "invalid")


@dataclass(frozen=True)
class Metric:
    """A registered metric: a function of the named inputs, over arrays of episodes."""

    name: str
    needs: tuple[str, ...]
    function: Callable[..., np.ndarray]
    description: str
    higher_is_better: bool = True
    tasks: tuple[str, ...] = ()  # empty: every task
    scene_types: tuple[str, ...] = ()  # empty: every scene type

    def applies(self, task: str, scene_type: str) -> bool:
        """Whether the metric is defined for an episode of this task and scene type."""
        in_tasks = not self.tasks or task in self.tasks
        return in_tasks and (not self.scene_types or scene_type in self.scene_types)


METRICS: dict[str, Metric] = {}
"""Registered metrics by name, in registration order."""


def metric(
    name: str,
    *,
    needs: Sequence[str],
    description: str,
    higher_is_better: bool = True,
    tasks: Sequence[str] = (),
    scene_types: Sequence[str] = (),
) -> Callable[[Callable[..., np.ndarray]], Callable[..., np.ndarray]]:
    """Register a metric computed from ``needs`` (measures, episode facts or earlier metrics)."""

    def register(function: Callable[..., np.ndarray]) -> Callable[..., np.ndarray]:
        if name in METRICS:
            raise ValueError(f"metric {name!r} is registered twice")
        METRICS[name] = Metric(
            name, tuple(needs), function, description, higher_is_better, tuple(tasks), tuple(scene_types)
        )
        return function

    return register


def _ratio(length: np.ndarray, path: np.ndarray) -> np.ndarray:
    """``L / max(L, P)``, 1 when both are 0."""
    top = np.maximum(length, path)
    return np.divide(length, top, out=np.ones_like(top), where=top > 0)


@metric("_label", needs=("fell", "dtg", "stopped", "success_distance", "valid"), description="label index")
def _label_code(fell, dtg, stopped, success_distance, valid):
    code = np.where(fell > 0, 2, np.where(dtg <= success_distance, 0, np.where(stopped > 0, 1, 3)))
    return np.where(valid > 0, code, 4)


@metric("success", needs=("_label",), description="SR: the episode ends within the success distance")
def _success(_label):
    return (_label == 0).astype(np.float64)


@metric("spl", needs=("success", "geodesic", "traveled"), description="success weighted by path length")
def _spl(success, geodesic, traveled):
    return success * _ratio(geodesic, np.nan_to_num(traveled))


@metric("soft_success", needs=("dtg", "dtg_start", "valid"), description="SS: max(0, 1 - d_T / d_0)")
def _soft_success(dtg, dtg_start, valid):
    progress = np.where(
        dtg_start > 0,
        np.maximum(0.0, 1.0 - np.divide(dtg, dtg_start, where=dtg_start > 0, out=np.zeros_like(dtg))),
        (dtg == 0),
    )
    return np.where(valid > 0, progress, 0.0)


@metric("soft_spl", needs=("soft_success", "geodesic", "traveled"), description="SS weighted by path length")
def _soft_spl(soft_success, geodesic, traveled):
    return soft_success * _ratio(geodesic, np.nan_to_num(traveled))


@metric("ne", needs=("dtg",), description="NE: distance to goal at the end (m)", higher_is_better=False)
def _ne(dtg):
    return dtg


@metric(
    "os",
    needs=("dtg_min", "success_distance", "valid"),
    description="OS: within the success distance at some time",
)
def _os(dtg_min, success_distance, valid):
    return ((dtg_min <= success_distance) & (valid > 0)).astype(np.float64)


@metric("ce", needs=("cells", "traveled"), description="CE: 1 m cells visited per meter traveled")
def _ce(cells, traveled):
    return cells / np.maximum(traveled, CE_EPSILON)


@metric("cr", needs=("collided",), description="CR: episodes with a collision", higher_is_better=False)
def _cr(collided):
    return collided


@metric("ado", needs=("clearance",), description="ADO: mean distance to the nearest obstacle (m)")
def _ado(clearance):
    return clearance


@metric("nsr", needs=("on_preferred",), description="NSR: share of time on preferred surfaces")
def _nsr(on_preferred):
    return on_preferred


@metric("path_length", needs=("traveled",), description="P: 3-D path length (m)", higher_is_better=False)
def _path_length(traveled):
    return traveled


@metric("speed", needs=("traveled", "duration"), description="mean speed (m/s)")
def _speed(traveled, duration):
    return np.divide(traveled, duration, out=np.zeros_like(traveled), where=duration > 0)


@metric("ndtw", needs=("dtw_score",), description="nDTW to the reference path (VLN)", tasks=("vln",))
def _ndtw(dtw_score):
    return dtw_score


@metric("sdtw", needs=("success", "ndtw"), description="success-weighted nDTW (VLN)", tasks=("vln",))
def _sdtw(success, ndtw):
    return success * ndtw


@metric(
    "ind_only",
    needs=("reached_outdoor",),
    description="Ind-Only: the robot never left the indoor region (indoor-to-outdoor)",
    higher_is_better=False,
    scene_types=TRANSITION_SCENE_TYPES,
)
def _ind_only(reached_outdoor):
    return 1.0 - reached_outdoor


@metric(
    "reach_out",
    needs=("reached_outdoor",),
    description="Reach-Out: the robot reached outdoors (indoor-to-outdoor)",
    scene_types=TRANSITION_SCENE_TYPES,
)
def _reach_out(reached_outdoor):
    return reached_outdoor


@metric(
    "ce_pre_exit",
    needs=("pre_exit_cells", "pre_exit_traveled"),
    description="CE before the exit: 1 m cells per meter up to the first row outdoors (indoor-to-outdoor)",
    scene_types=TRANSITION_SCENE_TYPES,
)
def _ce_pre_exit(pre_exit_cells, pre_exit_traveled):
    return pre_exit_cells / np.maximum(pre_exit_traveled, CE_EPSILON)


@metric(
    "ce_post_exit",
    needs=("post_exit_cells", "post_exit_traveled"),
    description="CE after the exit: 1 m cells per meter from the first row outdoors (indoor-to-outdoor)",
    scene_types=TRANSITION_SCENE_TYPES,
)
def _ce_post_exit(post_exit_cells, post_exit_traveled):
    return post_exit_cells / np.maximum(post_exit_traveled, CE_EPSILON)


def _post_exit(code: int) -> Callable[..., np.ndarray]:
    """The metric [label is `code`] over failed episodes that reached outdoors (NaN for the others)."""

    def share(_label: np.ndarray, reached_outdoor: np.ndarray) -> np.ndarray:
        failed_outside = (reached_outdoor > 0) & (_label != 0)
        return np.where(failed_outside, (_label == code).astype(np.float64), np.nan)

    return share


for _name, _what in (("wrong_goal", "wrong goals"), ("fall", "falls"), ("timeout", "timeouts")):
    metric(
        f"post_exit_{_name}",
        needs=("_label", "reached_outdoor"),
        description=f"share of {_what} among failed episodes that reached outdoors (indoor-to-outdoor)",
        higher_is_better=False,
        scene_types=TRANSITION_SCENE_TYPES,
    )(_post_exit(LABELS.index(_name)))


def compute_metrics(inputs: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Evaluate every registered metric over arrays of episodes.

    Parameters
    ----------
    inputs : mapping
        Per-episode arrays: the measures of :func:`~navverse.eval.measures.measure` (NaN for invalid
        episodes), ``geodesic``, ``success_distance`` and ``valid`` (1 for a scored trajectory, 0 for a
        missing or invalid one).

    Returns
    -------
    dict of ndarray
        Every metric by name, plus ``label`` (strings of :data:`LABELS`).
    """
    values: dict[str, np.ndarray] = {}

    def resolve(name: str, chain: tuple[str, ...]) -> np.ndarray:
        if name in values:
            return values[name]
        if name not in METRICS:
            if name in inputs:
                return np.asarray(inputs[name], dtype=np.float64)
            raise KeyError(f"{name!r} is neither a measure, an episode fact nor a registered metric")
        if name in chain:
            raise ValueError(f"metrics depend on each other in a cycle: {' -> '.join((*chain, name))}")
        spec = METRICS[name]
        arguments = {need: resolve(need, (*chain, name)) for need in spec.needs}
        values[name] = np.asarray(spec.function(**arguments), dtype=np.float64)
        return values[name]

    for name in METRICS:
        resolve(name, ())
    out = {name: values[name] for name in METRICS if not name.startswith("_")}
    out["label"] = np.array(LABELS, dtype=object)[values["_label"].astype(int)]
    return out
