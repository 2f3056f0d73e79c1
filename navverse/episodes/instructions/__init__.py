"""VLN instructions from an episode's reference path and its verification rollout (paper Appendix D.3).

One mechanism, in four steps, behind :class:`InstructionWriter`:

1. **Template.** The reference path is simplified (Douglas–Peucker, then segments shorter than
   ``min_segment`` are merged and vertices without a real turn dropped) into :class:`Directive` s:
   a start (turn from the start heading, walk the first segment), one turn per remaining vertex
   (signed angle classified by :func:`turn_class`), and an arrival naming the goal category.
   :func:`template_text` writes them with distances: "Turn left and walk forward about 4 meters,
   turn right and walk about 3 meters, then stop at the bed."
2. **Alignment.** Each directive is matched to the rollout time at which the robot carried it out,
   its closest approach to the directive's vertex, with times kept in path order
   (:func:`align_directives`): ``Instruction.directive_times``. An episode whose rollout stays
   farther than ``max_alignment_error`` from a directive's vertex is dropped.
3. **Landmarks.** Frames are ray-cast from the rollout's camera poses in a window before each turn
   (after the initial turn for the start, before the end for the arrival). Objects with at least
   ``min_pixels`` pixels at a mean depth of at most ``max_landmark_distance`` are candidates;
   distinctive ones (their category unique among the objects seen there, else made unique by their
   colour) are preferred, then larger and nearer ones. Each directive names at most one landmark,
   described by colour (:func:`object_color`, a small palette named by :func:`color_name`) and
   category. The text is rewritten from sentence patterns drawn with the episode's random generator,
   with no distances.
   Episodes with fewer than ``min_landmarks`` landmarks are dropped.
4. **Refiner (optional).** A callable (e.g. wrapping a vision-language model) receives keyframes
   (RGB at each directive's time), the template, the landmark text and the episode, and returns the
   final text (``instruction_type`` "refined"); :func:`load_refiner` imports one from
   ``"package.module:function"``. Without one the landmark text is the instruction ("landmark").

Example::

    writer = InstructionWriter(scene, camera_to_base=make_embodiment("spot").camera_to_base)
    instruction, reason = writer.write(episode, rollout, np.random.default_rng(seed))

``write`` returns ``(Instruction, None)``, or ``(None, reason)`` for a dropped episode. Rendering is
deterministic and the generator only chooses wording, so the same inputs and seed give the same
instruction.

Outdoors, segments that follow a road (on the walkway beside it, :class:`RoadFollowing`) are told as
following the street. PlaceNav episodes get this route instruction (naming the place, e.g. "stop at the
bank") and two more: the category ("Find a bank.") and an intention ("I need to withdraw some cash."),
from ``places``.

The modules: ``directives`` (steps 1 and 2: simplification, turns, alignment), ``landmarks`` (step 3:
what the camera sees, colour names), ``roads`` (segments along a road), ``wording`` (the template and
landmark texts), ``places`` (PlaceNav's place names, category and intention texts), ``writer`` (the
records, the refiner plug-in) and ``settings``. This package re-exports their public names.
"""

from navverse.episodes.instructions.directives import Directive, align_directives, plan_directives, turn_class
from navverse.episodes.instructions.landmarks import PALETTE, color_name, object_color
from navverse.episodes.instructions.places import (
    INTENTIONS,
    PLACE_NAMES,
    category_instruction,
    intention_instruction,
    place_phrase,
)
from navverse.episodes.instructions.roads import RoadFollowing
from navverse.episodes.instructions.settings import InstructionSettings
from navverse.episodes.instructions.wording import template_text
from navverse.episodes.instructions.writer import (
    DROP_REASONS,
    InstructionWriter,
    Refiner,
    RefinerError,
    load_refiner,
)

__all__ = [
    "DROP_REASONS",
    "INTENTIONS",
    "PALETTE",
    "PLACE_NAMES",
    "Directive",
    "InstructionSettings",
    "InstructionWriter",
    "Refiner",
    "RefinerError",
    "RoadFollowing",
    "align_directives",
    "category_instruction",
    "color_name",
    "intention_instruction",
    "load_refiner",
    "object_color",
    "place_phrase",
    "plan_directives",
    "template_text",
    "turn_class",
]
