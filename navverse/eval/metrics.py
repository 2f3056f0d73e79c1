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

Each public metric is declared once, here: besides its function, its full name (``title``), its short
name in tables (``abbreviation``), a one-line ``description``, its group mean as a LaTeX ``formula``, its
``unit`` and where the paper defines it (``reference``). The docs, ``tables.md``, ``report.html`` and
``metrics.json`` read them from :data:`METRICS`; registering a public metric without them fails. The
numbers per group of episodes that are not means of a metric (the label shares and the failure counts of
the failures and transition tables) are declared the same way in :data:`STATISTICS`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from navverse.eval.measures import TRANSITION_SCENE_TYPES

__all__ = ["LABELS", "METRICS", "STATISTICS", "UNITS", "Metric", "Statistic", "compute_metrics", "definition",
           "metric", "statistic", "termination_labels"]  # fmt: skip

CE_EPSILON = 1.0
"""``max(P, ε)`` in CE (m): a robot that does not move covers its own cell per meter."""
LABELS = ("success", "wrong_goal", "fall", "timeout", "invalid")
UNITS = ("%", "m", "cells/m", "m/s", "")
"""The units a metric or statistic is shown in: rates in %, lengths in m; "" for a count."""
APPENDIX_METRICS = "Appendix A.5 (Metrics)"
TRANSITION_TABLE = "Section 4.3, Table 4 (stage-wise transition analysis)"
FAILURE_TABLE = "Appendix A.6 (Termination labels), Table 5 (failure case analysis)"
"""Where the paper defines the metrics and labels (the ``reference`` of each declaration)."""
_REQUIRED = ("title", "abbreviation", "description", "formula")
"""The fields every public metric and statistic must fill in (docs and reports show them)."""


@dataclass(frozen=True)
class Metric:
    """A registered metric: a function of the named inputs, over arrays of episodes.

    Attributes
    ----------
    name : str
        Its key in ``metrics.json`` and the episode rows; ``_...`` for an internal one.
    needs : tuple of str
        The measures, episode facts or other metrics it is computed from.
    function : callable
        Computes it from `needs` (keyword arguments), one value per episode (NaN where undefined).
    description : str
        Its definition in words, on one line.
    higher_is_better : bool
        Whether a higher value is better.
    tasks, scene_types : tuple of str
        The tasks and scene types it is defined for (empty: all).
    title : str
        Its full name ("Success Rate").
    abbreviation : str
        Its short name in tables ("SR").
    formula : str
        Its group mean in LaTeX (for ``$$...$$``), over the ``N`` episodes where it is defined.
    unit : str
        One of :data:`UNITS`.
    reference : str
        Where the paper defines it ("" when it does not).
    """

    name: str
    needs: tuple[str, ...]
    function: Callable[..., np.ndarray]
    description: str
    higher_is_better: bool = True
    tasks: tuple[str, ...] = ()  # empty: every task
    scene_types: tuple[str, ...] = ()  # empty: every scene type
    title: str = ""
    abbreviation: str = ""
    formula: str = ""
    unit: str = ""
    reference: str = ""

    def applies(self, task: str, scene_type: str) -> bool:
        """Whether the metric is defined for an episode of this task and scene type."""
        in_tasks = not self.tasks or task in self.tasks
        return in_tasks and (not self.scene_types or scene_type in self.scene_types)


@dataclass(frozen=True)
class Statistic:
    """A number per group of episodes that is not the mean of a metric: a count, or a label's share.

    :func:`navverse.eval.scoring.group_means` computes each one of :data:`STATISTICS` for every group;
    the fields other than `function` are those of :class:`Metric`.
    """

    name: str
    function: Callable[[Sequence[Mapping[str, object]]], float]
    description: str
    higher_is_better: bool
    title: str
    abbreviation: str
    formula: str
    unit: str
    reference: str


METRICS: dict[str, Metric] = {}
"""Registered metrics by name, in registration order."""
STATISTICS: dict[str, Statistic] = {}
"""Registered group statistics by name, in the order :func:`~navverse.eval.scoring.group_means` writes
them after the metrics."""


def _check(kind: str, name: str, unit: str, fields: Mapping[str, str]) -> None:
    """Refuse a declaration that is registered twice, lacks a field docs and reports show, or is malformed.

    Raises
    ------
    ValueError
        If `name` is taken, a public one (not ``_...``) leaves a field of :data:`_REQUIRED` empty, its
        description spans lines, or `unit` is not one of :data:`UNITS`.
    """
    if name in METRICS or name in STATISTICS:
        raise ValueError(f"{kind} {name!r} is registered twice")
    if name.startswith("_"):
        return
    missing = [field for field in _REQUIRED if not fields[field].strip()]
    if missing:
        raise ValueError(f"{kind} {name!r} needs a {', '.join(missing)}: docs and reports show them")
    if "\n" in fields["description"]:
        raise ValueError(f"{kind} {name!r}: its description must be one line")
    if unit not in UNITS:
        raise ValueError(f"{kind} {name!r}: unit {unit!r} is not one of {UNITS}")


def metric(
    name: str,
    *,
    needs: Sequence[str],
    description: str,
    title: str = "",
    abbreviation: str = "",
    formula: str = "",
    unit: str = "",
    reference: str = "",
    higher_is_better: bool = True,
    tasks: Sequence[str] = (),
    scene_types: Sequence[str] = (),
) -> Callable[[Callable[..., np.ndarray]], Callable[..., np.ndarray]]:
    """Register a metric computed from ``needs`` (measures, episode facts or earlier metrics).

    The keyword arguments are the fields of :class:`Metric`. A public metric (not named ``_...``) must
    have a `title`, `abbreviation`, one-line `description` and `formula`.

    Raises
    ------
    ValueError
        If the name is taken or a public metric's declaration is incomplete (see :func:`_check`).
    """
    texts = {"title": title, "abbreviation": abbreviation, "description": description, "formula": formula}
    _check("metric", name, unit, texts)

    def register(function: Callable[..., np.ndarray]) -> Callable[..., np.ndarray]:
        METRICS[name] = Metric(
            name, tuple(needs), function, description, higher_is_better, tuple(tasks), tuple(scene_types),
            title, abbreviation, formula, unit, reference,
        )  # fmt: skip
        return function

    return register


def statistic(
    name: str,
    *,
    description: str,
    title: str,
    abbreviation: str,
    formula: str,
    unit: str,
    reference: str = "",
    higher_is_better: bool = False,
) -> Callable[[Callable[[Sequence[Mapping[str, object]]], float]], Callable]:
    """Register a group statistic: a function of a group's episode rows (see :class:`Statistic`).

    Raises
    ------
    ValueError
        As :func:`metric`.
    """
    texts = {"title": title, "abbreviation": abbreviation, "description": description, "formula": formula}
    _check("statistic", name, unit, texts)

    def register(function: Callable[[Sequence[Mapping[str, object]]], float]) -> Callable:
        STATISTICS[name] = Statistic(
            name, function, description, higher_is_better, title, abbreviation, formula, unit, reference
        )
        return function

    return register


def definition(name: str) -> Metric | Statistic:
    """The declaration of a metric or statistic, by name.

    Raises
    ------
    KeyError
        If `name` is neither.
    """
    if name in METRICS:
        return METRICS[name]
    if name in STATISTICS:
        return STATISTICS[name]
    raise KeyError(f"{name!r} is neither a registered metric nor a group statistic")


def _ratio(length: np.ndarray, path: np.ndarray) -> np.ndarray:
    """``L / max(L, P)``, 1 when both are 0."""
    top = np.maximum(length, path)
    return np.divide(length, top, out=np.ones_like(top), where=top > 0)


@metric("_label", needs=("fell", "dtg", "stopped", "success_distance", "valid"), description="label index")
def _label_code(fell, dtg, stopped, success_distance, valid):
    code = np.where(fell > 0, 2, np.where(dtg <= success_distance, 0, np.where(stopped > 0, 1, 3)))
    return np.where(valid > 0, code, 4)


@metric(
    "success",
    needs=("_label",),
    title="Success Rate",
    abbreviation="SR",
    description="Share of episodes that end within the success distance (1.0 m + robot radius) of a goal "
    "without falling; calling stop is not required.",
    formula=r"\mathrm{SR} = \frac{1}{N}\sum_{k=1}^{N}\mathbb{I}\left[d_T^{(k)} \le 1.0 + r_{\mathrm{robot}}"
    r" \wedge \neg\,\mathrm{fell}^{(k)}\right]",
    unit="%",
    reference=APPENDIX_METRICS,
)
def _success(_label):
    return (_label == 0).astype(np.float64)


@metric(
    "spl",
    needs=("success", "geodesic", "traveled"),
    title="Success weighted by Path Length",
    abbreviation="SPL",
    description="Success times the shortest-path length L over the longer of L and the executed path "
    "length P (the ratio is 1 when both are 0).",
    formula=r"\mathrm{SPL} = \frac{1}{N}\sum_{k=1}^{N}"
    r"\mathrm{SR}^{(k)}\,\frac{L^{(k)}}{\max(L^{(k)}, P^{(k)})}",
    unit="%",
    reference=APPENDIX_METRICS,
)
def _spl(success, geodesic, traveled):
    return success * _ratio(geodesic, np.nan_to_num(traveled))


@metric(
    "soft_success",
    needs=("dtg", "dtg_start", "valid"),
    title="Soft Success",
    abbreviation="SS",
    description="Progress toward the goal, max(0, 1 − d_T / d_0): the final over the initial distance to "
    "the goal (d_0 = 0 gives 1 only if d_T = 0).",
    formula=r"\mathrm{SS} = \frac{1}{N}\sum_{k=1}^{N}\max\left(0,\, 1 - \frac{d_T^{(k)}}{d_0^{(k)}}\right)",
    unit="%",
    reference=APPENDIX_METRICS,
)
def _soft_success(dtg, dtg_start, valid):
    progress = np.where(
        dtg_start > 0,
        np.maximum(0.0, 1.0 - np.divide(dtg, dtg_start, where=dtg_start > 0, out=np.zeros_like(dtg))),
        (dtg == 0),
    )
    return np.where(valid > 0, progress, 0.0)


@metric(
    "soft_spl",
    needs=("soft_success", "geodesic", "traveled"),
    title="Soft Success weighted by Path Length",
    abbreviation="SoftSPL",
    description="Soft success (SS) times the shortest-path length L over the longer of L and the executed "
    "path length P.",
    formula=r"\mathrm{SoftSPL} = \frac{1}{N}\sum_{k=1}^{N}"
    r"\max\left(0,\, 1 - \frac{d_T^{(k)}}{d_0^{(k)}}\right)"
    r"\,\frac{L^{(k)}}{\max(L^{(k)}, P^{(k)})}",
    unit="%",
    reference=APPENDIX_METRICS,
)
def _soft_spl(soft_success, geodesic, traveled):
    return soft_success * _ratio(geodesic, np.nan_to_num(traveled))


@metric(
    "ne",
    needs=("dtg",),
    title="Navigation Error",
    abbreviation="NE",
    description="Distance from the robot's final position to the nearest goal's edge (center distance "
    "minus the goal radius, at least 0).",
    formula=r"\mathrm{NE} = \frac{1}{N}\sum_{k=1}^{N}d_T^{(k)}",
    unit="m",
    reference=APPENDIX_METRICS,
    higher_is_better=False,
)
def _ne(dtg):
    return dtg


@metric(
    "os",
    needs=("dtg_min", "success_distance", "valid"),
    title="Oracle Success",
    abbreviation="OS",
    description="Share of episodes that come within the success distance of a goal at some time, "
    "whether or not they end there.",
    formula=r"\mathrm{OS} = \frac{1}{N}\sum_{k=1}^{N}\mathbb{I}\left[\min_{t \le T} d_t^{(k)}"
    r" \le 1.0 + r_{\mathrm{robot}}\right]",
    unit="%",
    reference=APPENDIX_METRICS,
)
def _os(dtg_min, success_distance, valid):
    return ((dtg_min <= success_distance) & (valid > 0)).astype(np.float64)


@metric(
    "ce",
    needs=("cells", "traveled"),
    title="Coverage Efficiency",
    abbreviation="CE",
    description="Distinct 1 m grid cells the path passes through per meter traveled (at least 1 m).",
    formula=r"\mathrm{CE} = \frac{1}{N}\sum_{k=1}^{N}"
    r"\frac{|\mathcal{G}(\tau^{(k)})|}{\max(P^{(k)}, 1\,\mathrm{m})}",
    unit="cells/m",
    reference=APPENDIX_METRICS,
)
def _ce(cells, traveled):
    return cells / np.maximum(traveled, CE_EPSILON)


@metric(
    "cr",
    needs=("collided",),
    title="Collision Rate",
    abbreviation="CR",
    description="Share of episodes with at least one collision with obstacle geometry (contact with the "
    "ground does not count).",
    formula=r"\mathrm{CR} = \frac{1}{N}\sum_{k=1}^{N}"
    r"\mathbb{I}\left[\exists\, t \le T:\ c_t^{(k)} = 1\right]",
    unit="%",
    reference=APPENDIX_METRICS,
    higher_is_better=False,
)
def _cr(collided):
    return collided


@metric(
    "ado",
    needs=("clearance",),
    title="Average Distance to Obstacles",
    abbreviation="ADO",
    description="Mean over an episode's rows of the distance from the robot base to the nearest obstacle.",
    formula=r"\mathrm{ADO} = \frac{1}{N}\sum_{k=1}^{N}"
    r"\frac{1}{T_k + 1}\sum_{t=0}^{T_k} d^{\mathrm{obs},(k)}_t",
    unit="m",
    reference=APPENDIX_METRICS,
)
def _ado(clearance):
    return clearance


@metric(
    "nsr",
    needs=("on_preferred",),
    title="Navigable Surface Ratio",
    abbreviation="NSR",
    description="Share of an episode's rows with the robot base on a surface preferred for its embodiment "
    "(e.g. floor, sidewalk, crosswalk).",
    formula=r"\mathrm{NSR} = \frac{1}{N}\sum_{k=1}^{N}\frac{1}{T_k + 1}\sum_{t=0}^{T_k} n^{(k)}_t",
    unit="%",
    reference=APPENDIX_METRICS,
)
def _nsr(on_preferred):
    return on_preferred


@metric(
    "path_length",
    needs=("traveled",),
    title="Path Length",
    abbreviation="P",
    description="Length of the executed path, summed in 3-D over consecutive scored rows.",
    formula=r"P = \frac{1}{N}\sum_{k=1}^{N}\sum_{t=1}^{T_k}"
    r" \lVert \mathbf{p}^{(k)}_t - \mathbf{p}^{(k)}_{t-1} \rVert_2",
    unit="m",
    reference=APPENDIX_METRICS,
    higher_is_better=False,
)
def _path_length(traveled):
    return traveled


@metric(
    "speed",
    needs=("traveled", "duration"),
    title="Mean Speed",
    abbreviation="Speed",
    description="Path length over the time from the first to the last scored row (0 when no time passes).",
    formula=r"\bar{v} = \frac{1}{N}\sum_{k=1}^{N}\frac{P^{(k)}}{t^{(k)}_T - t^{(k)}_0}",
    unit="m/s",
)
def _speed(traveled, duration):
    return np.divide(traveled, duration, out=np.zeros_like(traveled), where=duration > 0)


@metric(
    "ndtw",
    needs=("dtw_score",),
    title="Normalized Dynamic Time Warping",
    abbreviation="nDTW",
    description="How closely the path follows the reference path, exp(−DTW / (|R| · d_th)), both resampled "
    "every 0.5 m in the horizontal plane (VLN).",
    formula=r"\mathrm{nDTW} = \frac{1}{N}\sum_{k=1}^{N}"
    r"\exp\left(-\frac{\mathrm{DTW}(Q^{(k)}, R^{(k)})}{|R^{(k)}|\,(1.0 + r_{\mathrm{robot}})}\right)",
    unit="%",
    tasks=("vln",),
)
def _ndtw(dtw_score):
    return dtw_score


@metric(
    "sdtw",
    needs=("success", "ndtw"),
    title="Success weighted by normalized Dynamic Time Warping",
    abbreviation="SDTW",
    description="nDTW of the successful episodes, 0 for the failed ones (VLN).",
    formula=r"\mathrm{SDTW} = \frac{1}{N}\sum_{k=1}^{N}\mathrm{SR}^{(k)}\,\mathrm{nDTW}^{(k)}",
    unit="%",
    tasks=("vln",),
)
def _sdtw(success, ndtw):
    return success * ndtw


@metric(
    "ind_only",
    needs=("reached_outdoor",),
    title="Indoor Only",
    abbreviation="Ind-Only",
    description="Share of indoor-to-outdoor episodes in which the robot never left the indoor region.",
    formula=r"\mathrm{Ind\text{-}Only} = \frac{1}{N}\sum_{k=1}^{N}"
    r"\mathbb{I}\left[\nexists\, t \le T:\ \mathbf{p}^{(k)}_t \notin \mathrm{indoor}\right]",
    unit="%",
    reference=TRANSITION_TABLE,
    higher_is_better=False,
    scene_types=TRANSITION_SCENE_TYPES,
)
def _ind_only(reached_outdoor):
    return 1.0 - reached_outdoor


@metric(
    "reach_out",
    needs=("reached_outdoor",),
    title="Reached Outdoors",
    abbreviation="Reach-Out",
    description="Share of indoor-to-outdoor episodes in which the robot reached outdoors (1 − Ind-Only).",
    formula=r"\mathrm{Reach\text{-}Out} = \frac{1}{N}\sum_{k=1}^{N}"
    r"\mathbb{I}\left[\exists\, t \le T:\ \mathbf{p}^{(k)}_t \notin \mathrm{indoor}\right]",
    unit="%",
    reference=TRANSITION_TABLE,
    scene_types=TRANSITION_SCENE_TYPES,
)
def _reach_out(reached_outdoor):
    return reached_outdoor


@metric(
    "ce_pre_exit",
    needs=("pre_exit_cells", "pre_exit_traveled"),
    title="Coverage Efficiency before the Exit",
    abbreviation="CE pre-exit",
    description="CE of the path up to the first row outdoors, the exit row e (all rows if it never exits; "
    "undefined when it starts outdoors).",
    formula=r"\mathrm{CE}_{\mathrm{pre}} = \frac{1}{N}\sum_{k=1}^{N}"
    r"\frac{|\mathcal{G}(\tau^{(k)}_{0..e_k})|}{\max(P^{(k)}_{0..e_k}, 1\,\mathrm{m})}",
    unit="cells/m",
    reference=TRANSITION_TABLE,
    scene_types=TRANSITION_SCENE_TYPES,
)
def _ce_pre_exit(pre_exit_cells, pre_exit_traveled):
    return pre_exit_cells / np.maximum(pre_exit_traveled, CE_EPSILON)


@metric(
    "ce_post_exit",
    needs=("post_exit_cells", "post_exit_traveled"),
    title="Coverage Efficiency after the Exit",
    abbreviation="CE post-exit",
    description="CE of the path from the first row outdoors, the exit row e, to the end (undefined when "
    "the robot never exits).",
    formula=r"\mathrm{CE}_{\mathrm{post}} = \frac{1}{N}\sum_{k=1}^{N}"
    r"\frac{|\mathcal{G}(\tau^{(k)}_{e_k..T_k})|}{\max(P^{(k)}_{e_k..T_k}, 1\,\mathrm{m})}",
    unit="cells/m",
    reference=TRANSITION_TABLE,
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


_LABEL_WORDS = {
    "success": ("success", "Success", "succeeded (the row's SR)"),
    "wrong_goal": ("wrong goal", "Wrong Goal", "stopped outside the success distance (a wrong goal)"),
    "fall": ("fall", "Fall", "fell (tilt beyond 45°)"),
    "timeout": ("timeout", "Timeout", "neither stopped nor reached the goal within their time (300 s)"),
    "invalid": ("invalid", "Invalid", "have no valid trajectory in the submission (scored as failures)"),
}
"""Per label: its column name, its title and what its episodes did."""

for _name in ("wrong_goal", "fall", "timeout"):
    _short, _title, _did = _LABEL_WORDS[_name]
    metric(
        f"post_exit_{_name}",
        needs=("_label", "reached_outdoor"),
        title=f"Post-Exit {_title} Share",
        abbreviation=f"post-exit {_short}",
        description=f"Share of the failed indoor-to-outdoor episodes that reached outdoors and {_did}.",
        formula=r"\frac{1}{|F_{\mathrm{out}}|}\sum_{k \in F_{\mathrm{out}}}"
        + r"\mathbb{I}\left[\ell^{(k)} = \text{"
        + _short
        + r"}\right]",
        unit="%",
        reference=TRANSITION_TABLE,
        higher_is_better=False,
        scene_types=TRANSITION_SCENE_TYPES,
    )(_post_exit(LABELS.index(_name)))


def _label_share(label: str) -> Callable[[Sequence[Mapping[str, object]]], float]:
    """The share of a group's episodes with this termination label."""

    def share(rows: Sequence[Mapping[str, object]]) -> float:
        return sum(row["label"] == label for row in rows) / len(rows)

    return share


for _name in LABELS:
    _short, _title, _did = _LABEL_WORDS[_name]
    statistic(
        f"{_name}_share",
        title=f"{_title} Share",
        abbreviation=_short,
        description=f"Share of all the row's episodes (not only the failed ones) that {_did}.",
        formula=r"\frac{1}{N}\sum_{k=1}^{N}\mathbb{I}\left[\ell^{(k)} = \text{" + _short + r"}\right]",
        unit="%",
        reference={"success": APPENDIX_METRICS, "invalid": ""}.get(_name, FAILURE_TABLE),
        higher_is_better=_name == "success",
    )(_label_share(_name))


@statistic(
    "failures",
    title="Failed Episodes",
    abbreviation="#Fail",
    description="Number of the row's episodes that did not succeed (any label but success).",
    formula=r"\#\mathrm{Fail} = \sum_{k=1}^{N}\mathbb{I}\left[\ell^{(k)} \ne \text{success}\right]",
    unit="",
    reference=FAILURE_TABLE,
)
def _failures(rows: Sequence[Mapping[str, object]]) -> int:
    return sum(row["label"] != "success" for row in rows)


@statistic(
    "post_exit_failures",
    title="Post-Exit Failed Episodes",
    abbreviation="#post-exit fail",
    description="Number of failed indoor-to-outdoor episodes that reached outdoors: the n of the post-exit "
    "shares.",
    formula=r"|F_{\mathrm{out}}| = \sum_{k=1}^{N}\mathbb{I}\left[\ell^{(k)} \ne \text{success} \wedge "
    r"\exists\, t \le T:\ \mathbf{p}^{(k)}_t \notin \mathrm{indoor}\right]",
    unit="",
    reference=TRANSITION_TABLE,
)
def _post_exit_failures(rows: Sequence[Mapping[str, object]]) -> int:
    return sum(row.get("post_exit_timeout") is not None for row in rows)


def termination_labels(inputs: Mapping[str, np.ndarray]) -> np.ndarray:
    """The termination label of each episode, as :func:`compute_metrics` gives it, from only the inputs
    the label needs (``fell``, ``dtg``, ``stopped``, ``success_distance``, ``valid``).

    Parameters
    ----------
    inputs : mapping
        Per-episode arrays (other keys are ignored).

    Returns
    -------
    ndarray of str
        Strings of :data:`LABELS`.
    """
    spec = METRICS["_label"]
    arguments = {need: np.asarray(inputs[need], dtype=np.float64) for need in spec.needs}
    code = np.asarray(spec.function(**arguments), dtype=np.float64)
    return np.array(LABELS, dtype=object)[code.astype(int)]


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
