"""Which targets a command works on: selectors over the loaded recipes, and broken recipe files.

A recipe file with problems makes no target (:class:`BrokenRecipe`). A command fails on the broken
files its selection needs — everything selected, a selector naming the file or its folder, an id or
glob that matches no good target but might name one of its targets, or a ``links`` glob of the build
graph that might match one of its targets (the build would silently differ) — and otherwise goes
ahead with a warning per broken file.
"""

from __future__ import annotations

import fnmatch
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from pipeline.errors import RecipeError, RecipeIssue, TargetError

if TYPE_CHECKING:
    from pipeline.recipes import Target


@dataclass(frozen=True)
class BrokenRecipe:
    """A recipe file that has problems, so that none of its targets exist.

    Attributes
    ----------
    file : str
        Its path relative to the recipes folder (POSIX form), as in its problems.
    issues : tuple of RecipeIssue
        Its problems (some may be in a file it extends).
    base_id : str
        The id its targets would start with (``<id>``, ``<id>-s<seed>``, ``<id>-<index>``): its
        ``id`` if its text gives one, else its file name's stem.
    """

    file: str
    issues: tuple[RecipeIssue, ...]
    base_id: str

    def may_define(self, pattern: str) -> bool:
        """Whether a target id (or glob) ``pattern`` might name one of this file's targets.

        Errs towards yes: the file's ids are known only by their start.
        """
        literal = re.split(r"[*?\[]", pattern, maxsplit=1)[0]
        if literal == pattern:  # an exact id: this file's own id, or one of its expansions
            return pattern == self.base_id or pattern.startswith(f"{self.base_id}-")
        return self.base_id.startswith(literal) or literal.startswith(self.base_id)


@dataclass(frozen=True)
class RecipeSet:
    """The recipes of a workspace as loaded: the targets of the good files, and the broken files.

    Attributes
    ----------
    targets : tuple of Target
        Every target of the files without problems.
    broken : tuple of BrokenRecipe
        The files with problems, in the order loaded.
    """

    targets: tuple[Target, ...]
    broken: tuple[BrokenRecipe, ...]

    def error(self, broken: Iterable[BrokenRecipe] | None = None) -> RecipeError:
        """One :class:`RecipeError` with the problems of ``broken`` (default: every broken file)."""
        files = self.broken if broken is None else broken
        return RecipeError([issue for recipe in files for issue in recipe.issues])

    def skipped_note(self) -> str:
        """A sentence naming the broken files, for errors that they may have caused."""
        names = ", ".join(recipe.file for recipe in self.broken)
        return (
            f"(recipe files skipped for their problems, whose targets do not exist: {names}; "
            "navverse validate recipe lists their problems)"
        )


def _selector_key(selector: str) -> tuple[str, str]:
    """A selector as an id or glob (``key``) and as a recipe path without ``.yaml`` (``stem``)."""
    key = selector.strip().removeprefix("recipes/").rstrip("/")
    return key, key.removesuffix(".yaml")


def select_targets(targets: Sequence[Target], selectors: Sequence[str]) -> list[Target]:
    """Targets matching any selector: a target id (glob allowed) or a recipe path prefix.

    ``scenes`` selects every recipe under ``recipes/scenes``; ``scenes/indoor/office.yaml`` one file;
    ``office-*`` the targets whose id matches. No selector selects everything. Targets of a ``manual``
    recipe are only selected by their exact id or their recipe file.

    Raises
    ------
    TargetError
        If a selector matches nothing.
    """
    if not selectors:
        return [t for t in targets if not t.manual]
    chosen: dict[str, Target] = {}
    for selector in selectors:
        key, stem = _selector_key(selector)
        matched = [
            t
            for t in targets
            if t.id == key
            or t.recipe == f"{stem}.yaml"
            or (not t.manual and (fnmatch.fnmatchcase(t.id, key) or t.recipe.startswith(f"{stem}/")))
        ]
        if not matched:
            some = ", ".join(sorted(t.id for t in targets)[:12])
            raise TargetError(f"no target or recipe matches {selector!r} (targets include: {some})")
        for target in matched:
            chosen[target.id] = target
    return [chosen[k] for k in sorted(chosen)]


def select_loaded(recipes: RecipeSet, selectors: Sequence[str]) -> list[Target]:
    """:func:`select_targets` over the good files of ``recipes``, unless the selection needs a broken one.

    A broken file is needed, and its problems are the error, when no selector is given (everything
    is selected), when a selector names it or a folder holding it, or when a selector matches no
    target of the good files but might name one of its targets. Other broken files do not block:
    :func:`skipped_warnings` tells about them.

    Raises
    ------
    RecipeError
        With the problems of every broken file the selection needs.
    TargetError
        If a selector matches nothing (the message names the broken files, in case).
    """
    if not recipes.broken:
        return select_targets(recipes.targets, selectors)
    if not selectors:
        raise recipes.error()
    needed: dict[str, BrokenRecipe] = {}
    for selector in selectors:
        key, stem = _selector_key(selector)
        for recipe in recipes.broken:
            named = recipe.file == f"{stem}.yaml" or recipe.file.startswith(f"{stem}/")
            if named or (recipe.may_define(key) and not _selects_any(recipes.targets, selector)):
                needed[recipe.file] = recipe
    if needed:
        raise recipes.error(needed.values())
    try:
        return select_targets(recipes.targets, selectors)
    except TargetError as exc:
        raise TargetError(f"{exc}\n{recipes.skipped_note()}") from None


def _selects_any(targets: Sequence[Target], selector: str) -> bool:
    try:
        select_targets(targets, [selector])
    except TargetError:
        return False
    return True


def linked_broken(recipes: RecipeSet, targets: Iterable[Target]) -> list[BrokenRecipe]:
    """The broken files whose targets a ``links`` glob of ``targets`` might match.

    Such a link would silently read fewer targets than the recipes say (a dataset without a scene,
    say), so the build needs those files fixed first.
    """
    patterns = {pattern for target in targets for link in target.links.values() for pattern in link.targets}
    return [recipe for recipe in recipes.broken if any(recipe.may_define(p) for p in sorted(patterns))]


def skipped_warnings(recipes: RecipeSet, *, selectors: Sequence[str]) -> list[str]:
    """Warnings about the broken files a selection went without, one per file.

    Each names the file, the command that lists its problems, and the selectors that might have
    matched its targets, which are missing from what they select.
    """
    warnings = []
    for recipe in recipes.broken:
        count = len(recipe.issues)
        lines = [
            f"skipped recipes/{recipe.file} ({count} problem{'s' if count != 1 else ''}; "
            f"see navverse validate recipe recipes/{recipe.file}): its targets do not exist"
        ]
        lines += [
            f"  selector {selector!r} might have matched targets of it"
            for selector in selectors
            if recipe.may_define(_selector_key(selector)[0])
        ]
        warnings.append("\n".join(lines))
    return warnings
