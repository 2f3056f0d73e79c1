"""The wording of instructions: the template text, and the landmark text rewritten from sentence patterns.

:func:`template_text` writes directives with their distances ("Turn left and walk forward about 4
meters, turn right and walk about 3 meters, then stop at the bed."); :func:`landmark_text` writes them
with their landmarks and no distances, one sentence pattern per directive drawn with the episode's
random generator (which chooses the wording only).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from navverse.episodes.instructions.directives import Directive

if TYPE_CHECKING:
    from navverse.episodes.instructions.landmarks import SeenLandmark

__all__ = ["category_words", "landmark_text", "template_text"]

_TEMPLATE_TURN = {
    "straight": "continue straight",
    "slight_left": "turn slightly left",
    "slight_right": "turn slightly right",
    "left": "turn left",
    "right": "turn right",
    "sharp_left": "turn sharply left",
    "sharp_right": "turn sharply right",
    "around": "turn around",
}


def _meters(length: float) -> str:
    n = max(1, round(length))
    return f"about {n} meter" + ("" if n == 1 else "s")


def template_text(directives: Sequence[Directive], goal: str) -> str:
    """The template instruction: turns and distances, then the arrival at `goal` (a category).

    Parameters
    ----------
    directives : sequence of Directive
        From :func:`~navverse.episodes.instructions.directives.plan_directives`.
    goal : str
        Goal category (underscores read as spaces).

    Returns
    -------
    str
        E.g. "Turn left and walk forward about 4 meters, turn right and walk about 3 meters, then stop
        at the bed."
    """
    clauses = []
    for d in directives:
        if d.kind == "start":
            walk = f"walk forward {_meters(d.length)}"
            clauses.append(walk if d.turn == "straight" else f"{_TEMPLATE_TURN[d.turn]} and {walk}")
        elif d.kind == "turn":
            clauses.append(f"{_TEMPLATE_TURN[d.turn]} and walk {_meters(d.length)}")
    clauses.append(f"then stop at the {category_words(goal)}.")
    text = ", ".join(clauses)
    return text[0].upper() + text[1:]


def category_words(category: str) -> str:
    """A category as read in a sentence: underscores as spaces, initialisms ("tv", "suv") in capitals."""
    return " ".join(w.upper() if w in _INITIALISMS else w for w in category.replace("_", " ").split())


_INITIALISMS = frozenset({"tv", "suv", "atm"})


# Sentence patterns of the landmark text, by situation; {verb} is a turn (_VERBS), {lm} a landmark
# ("the" is in the pattern), {dist} a length in words, {goal} the goal category.
# fmt: off
_VERBS = {
    "slight": ("bear slightly {side}", "veer slightly {side}", "turn slightly {side}"),
    "turn": ("turn {side}", "go {side}", "take a {side}"),
    "sharp": ("make a sharp {side}", "turn sharply {side}", "take a hard {side}"),
    "around": ("turn around", "turn back", "make a U-turn"),
}
_PATTERNS = {
    "start": ("walk forward {dist}", "go straight ahead {dist}", "move ahead {dist}"),
    "start+lm": ("head towards the {lm}", "walk forward past the {lm}", "go ahead, passing the {lm}",
                 "start by walking towards the {lm}"),
    "start_turn": ("{verb} and walk forward {dist}", "{verb} and go ahead {dist}",
                   "first {verb}, then walk {dist}"),
    "start_turn+lm": ("{verb} and head towards the {lm}", "{verb}, then walk past the {lm}",
                      "first {verb} and walk towards the {lm}", "{verb} and go ahead, passing the {lm}"),
    "turn": ("{verb}", "{verb} and keep walking {dist}", "{verb} and walk {dist}"),
    "turn+lm": ("{verb} at the {lm}", "when you reach the {lm}, {verb}", "at the {lm}, {verb}",
                "{verb} once you get to the {lm}", "{verb} by the {lm} and walk {dist}",
                "{verb} when you see the {lm}"),
    "arrive": ("stop by the {goal}", "stop when you reach the {goal}", "your goal is the {goal}"),
    "arrive+near": ("stop by the {goal} next to the {lm}", "your goal is the {goal} near the {lm}",
                    "stop at the {goal}, close to the {lm}", "the {goal} beside the {lm} is your goal"),
    "arrive+pass": ("walk past the {lm} and stop by the {goal}", "pass the {lm} and stop at the {goal}",
                    "continue past the {lm} to the {goal}"),
    # the segment follows a road (outdoors): the street is the landmark
    "start+road": ("walk along the street", "follow the sidewalk along the road",
                   "keep to the sidewalk and follow the street"),
    "start_turn+road": ("{verb} and walk along the street", "{verb} and follow the road",
                        "{verb}, then keep to the sidewalk along the street"),
    "turn+road": ("{verb} and follow the street", "{verb} and walk along the road",
                  "{verb} and keep to the sidewalk along the street"),
    # the goal was not seen on the way: the paper's "you will arrive at [target]"
    "arrive_unseen": ("you will arrive at the {goal}",),
    "arrive_unseen+near": ("you will arrive at the {goal} near the {lm}",),
    "arrive_unseen+pass": ("pass the {lm} and you will arrive at the {goal}",),
}
_EXIT_CLAUSES = (
    ", then leave the building through the front door",
    " and go out through the exit",
    ", then step out of the building through the door",
)
_JOINERS = (". ", ". Then ", ", then ", ". After that, ", ". Next, ")
_FINAL_JOINERS = (". ", ". Finally, ")
# fmt: on


def _distance_words(length: float) -> str:
    if length < 2.0:
        return "a few steps"
    if length < 4.0:
        return "a short distance"
    return "a while" if length < 7.0 else "a long way"


def _verb(turn: str, rng: np.random.Generator) -> str:
    kind, _, side = turn.partition("_")
    if kind in ("left", "right"):
        kind, side = "turn", kind
    return str(rng.choice(_VERBS[kind])).format(side=side)


def landmark_text(
    directives: Sequence[Directive],
    landmarks: Sequence[SeenLandmark | None],
    goal: str,
    *,
    goal_seen: bool,
    rng: np.random.Generator,
    along_road: Sequence[bool] | None = None,
    exit_at: int | None = None,
) -> str:
    """The landmark-grounded instruction: one pattern per directive, drawn with `rng`; no distances.

    Parameters
    ----------
    directives : sequence of Directive
        The directives, in path order.
    landmarks : sequence of SeenLandmark or None
        The landmark of each directive, or None.
    goal : str
        Goal category (underscores read as spaces).
    goal_seen : bool
        Whether the goal was seen before arriving; if not, the arrival says "you will arrive at".
    rng : numpy.random.Generator
        Chooses the patterns, turn verbs and joiners.
    along_road : sequence of bool, optional
        For each directive, whether the segment walked after it follows a road; such a segment
        without a landmark is told as following the street, and with one gets ", following the
        street" (outdoor routes).
    exit_at : int, optional
        The directive during whose walk the route leaves the building (indoor-to-outdoor routes):
        its clause goes on with leaving the building through the door.

    Returns
    -------
    str
        The instruction, sentences capitalised, ending with a full stop.
    """
    clauses = []
    roads = list(along_road) if along_road is not None else [False] * len(directives)
    for d, lm, road in zip(directives, landmarks, roads, strict=True):
        if d.kind == "start":
            situation = "start" if d.turn == "straight" else "start_turn"
        else:
            situation = d.kind if d.kind == "turn" or goal_seen else "arrive_unseen"
        follows = road and d.kind != "arrive"
        if lm is not None:
            situation += "+lm" if d.kind != "arrive" else "+near" if lm.near_goal else "+pass"
        elif follows:
            situation += "+road"
        fields = {
            "verb": "" if d.turn == "straight" else _verb(d.turn, rng),
            "lm": "" if lm is None else lm.phrase,
            "dist": _distance_words(d.length),
            "goal": category_words(goal),
        }
        patterns = _PATTERNS[situation]
        clause = patterns[int(rng.integers(len(patterns)))].format(**fields)
        clause += ", following the street" if follows and lm is not None else ""
        if exit_at is not None and len(clauses) == exit_at:
            clause += str(rng.choice(_EXIT_CLAUSES))
        clauses.append(clause)
    text = clauses[0]
    for i, clause in enumerate(clauses[1:], start=1):
        joiner = str(rng.choice(_FINAL_JOINERS if i == len(clauses) - 1 else _JOINERS))
        text += joiner + (clause[0].upper() + clause[1:] if joiner == ". " else clause)
    return text[0].upper() + text[1:] + "."
