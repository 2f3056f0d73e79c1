"""Recipes: YAML files validated into targets.

A recipe names the stages of a target and their parameters::

    description: A two-room blockout.
    extends: blockout-indoor          # a preset in recipes/presets/, or a path ending in .yaml
    seeds: [0, 1, 2]                  # three targets: <id>-s0, <id>-s1, <id>-s2  (or count: N)
    stages:
      blockout: {size: [10, 6, 3]}
      decimate: null                  # null removes a stage inherited from a preset
    links:
      scene: ["apartment-*"]          # input 'scene' reads artifact 'scene' of other targets
      building: {artifact: geometry, targets: [apartment-s0]}   # input 'building' reads their 'geometry'

A stage that declares a passthrough can be skipped: ``stages: {storefronts: {skip: true}}``.

Every problem in every file is collected and reported at once, with file, line and key path.
"""

from __future__ import annotations

import copy
import os
import re
import reprlib
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    StrictBool,
    StrictInt,
    ValidationError,
    field_validator,
    model_validator,
)

from pipeline.errors import RecipeError, RecipeIssue, StageImportError
from pipeline.hashing import hash_value
from pipeline.params import Params
from pipeline.selection import BrokenRecipe, RecipeSet
from pipeline.stage import SKIP_KEY, StageSpec, registered_stages
from pipeline.workspace import Workspace
from pipeline.yaml_source import KeyPath, Located, YamlSourceError, load_located

TARGET_ID_PATTERN = r"^[a-z0-9][a-z0-9._-]*$"
ARTIFACT_PATTERN = r"^[a-z][a-z0-9_]*$"
PRESET_NAME_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9._-]*$"
"""A preset is named by its file's stem: no folders, no path."""

MAX_EXTENDS_FILES = 64
"""Most files one recipe may reach through ``extends`` (its presets, theirs, and so on; repeats count)."""

MAX_SHOWN_INPUT = 80
"""Characters of an offending value quoted in a message."""

MAX_ISSUES_PER_FILE = 50
"""Problems listed per recipe file; the rest are counted."""


class LinkModel(BaseModel):
    """A link that renames: the input reads artifact ``artifact`` of the ``targets``."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    artifact: Annotated[str, Field(pattern=ARTIFACT_PATTERN)]
    targets: Annotated[list[str], Field(min_length=1)]


class RecipeModel(BaseModel):
    """Top level of a recipe file (after ``extends`` is resolved)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    id: Annotated[str, Field(pattern=TARGET_ID_PATTERN)] | None = None
    description: str = ""
    # Strict: YAML 1.1 reads `yes`/`no`/`on`/`off` as booleans, which must not pass for 1 and 0.
    seed: Annotated[StrictInt, Field(ge=0)] = 0
    seeds: list[Annotated[StrictInt, Field(ge=0)]] | None = None
    count: Annotated[StrictInt, Field(ge=1, le=100_000)] | None = None
    stages: dict[str, dict[str, Any]]
    links: dict[Annotated[str, Field(pattern=ARTIFACT_PATTERN)], list[str] | LinkModel] = {}
    manual: StrictBool = False

    @field_validator("stages", mode="before")
    @classmethod
    def _stages_are_mappings(cls, value: Any) -> Any:
        if isinstance(value, dict):
            for name, section in value.items():
                if section is None:
                    continue
                if not isinstance(section, dict):
                    raise ValueError(f"stage {name!r} must map parameter names to values")
        return value

    @model_validator(mode="after")
    def _one_expansion(self) -> RecipeModel:
        if self.seeds is not None and self.count is not None:
            raise ValueError("give either 'seeds' or 'count', not both")
        if self.seeds is not None and (not self.seeds or len(set(self.seeds)) != len(self.seeds)):
            raise ValueError("'seeds' must be a non-empty list of distinct integers")
        if not self.stages:
            raise ValueError("a recipe needs at least one stage under 'stages'")
        return self


@dataclass(frozen=True)
class StageCall:
    """One stage of a target, with its validated parameters.

    A skipped call (``skip: true`` in the recipe) runs nothing: each output is its passthrough input.
    """

    spec: StageSpec
    params: Params
    skip: bool = False


@dataclass(frozen=True)
class Link:
    """Where a target's input comes from: artifact ``artifact`` of the targets matching ``targets``.

    ``artifact`` is ``None`` when the input reads the artifact its stage declares (by default, the
    artifact of the input's own name).
    """

    targets: tuple[str, ...]
    artifact: str | None = None

    def describe(self, input_name: str) -> str:
        """The link as a recipe would write it, for messages."""
        source = f"artifact {self.artifact!r} of " if self.artifact else ""
        return f"{input_name!r} ({source}{', '.join(self.targets)})"


@dataclass(frozen=True)
class Target:
    """A buildable unit expanded from a recipe.

    Attributes
    ----------
    id : str
        Unique target id (e.g. ``apartment-s1``).
    recipe : str
        Recipe path relative to the recipes folder (POSIX form).
    recipe_hash : str
        Hash of the recipe after ``extends`` and expansion, without the sections of appearance stages
        (:attr:`pipeline.stage.StageSpec.appearance`): stages record it in what they write, and a
        changed look must change nothing else.
    seed : int
        The recipe seed of this target (stage seeds derive from it).
    stages : tuple of StageCall
        The target's stages, sorted by name (order of execution comes from the graph).
    links : dict
        ``{input name: Link}`` for inputs taken from other targets.
    description : str
        The recipe's description.
    manual : bool
        Built only when selected by its id or its recipe file, never by a folder or by building
        everything (a large configuration that needs a cluster, say).
    """

    id: str
    recipe: str
    recipe_hash: str
    seed: int
    stages: tuple[StageCall, ...]
    links: dict[str, Link]
    description: str = ""
    manual: bool = False


def _merge(base: Located, over: Located) -> Located:
    """Deep-merge ``over`` onto ``base``: mappings merge, other values replace, ``null`` deletes.

    Every key path keeps the mark of the file its value comes from (time linear in the data).
    """
    data = copy.deepcopy(base.data) if isinstance(base.data, dict) else {}
    if isinstance(over.data, dict):
        _merge_data(data, over.data, top=True)
    marks: dict[KeyPath, tuple[str, int]] = {}
    stack: list[tuple[KeyPath, Any]] = [((), data)]
    while stack:
        path, value = stack.pop()
        mark = over.marks.get(path) or base.marks.get(path)
        if mark is not None:
            marks[path] = mark
        if isinstance(value, dict):
            stack.extend(((*path, key), item) for key, item in value.items())
        elif isinstance(value, list):
            stack.extend(((*path, index), item) for index, item in enumerate(value))
    marks[()] = over.marks.get((), ("<unknown>", 0))
    return Located(data, marks)


def _merge_data(target: dict[str, Any], source: dict[str, Any], *, top: bool) -> None:
    for key, value in source.items():
        if value is None and not top:  # 'key: null' below the top level removes an inherited entry
            target.pop(key, None)
        elif isinstance(value, dict) and isinstance(target.get(key), dict):
            _merge_data(target[key], value, top=False)
        else:
            target[key] = copy.deepcopy(value)


class RecipeLoader:
    """Loads recipe files of a workspace into targets, collecting every problem found.

    Parameters
    ----------
    workspace : Workspace
        Where recipes and presets are.
    stages : mapping, optional
        Stage registry to validate against (default: every registered stage), e.g. a
        :class:`~pipeline.stage.StageIndex`, which imports the stages the recipes name.
    """

    def __init__(self, workspace: Workspace, *, stages: Mapping[str, StageSpec] | None = None) -> None:
        self.workspace = workspace
        self.stages = registered_stages() if stages is None else stages
        self.issues: list[RecipeIssue] = []
        self._extended: dict[Path, Located | YamlSourceError] = {}  # files reached through 'extends'
        self._followed = 0  # files reached through 'extends' by the recipe being loaded
        self._own_id: str | None = None  # the 'id' the text of the recipe being loaded gives

    # -- discovery ---------------------------------------------------------------------------
    def recipe_files(self) -> list[Path]:
        """Every recipe file of the workspace (presets excluded), sorted."""
        root = self.workspace.recipes_dir
        presets = self.workspace.presets_dir
        return sorted(p for p in root.rglob("*.yaml") if not p.is_relative_to(presets))

    def _relative(self, path: Path) -> str:
        """``path`` relative to the recipes folder (POSIX form), else as given.

        A symbolic link is shown where it is (it may lead nowhere).
        """
        recipes = self.workspace.recipes_dir
        for inside, folder in (
            (Path(os.path.abspath(path)), Path(os.path.abspath(recipes))),
            (_real(path), _real(recipes)),
        ):
            if inside.is_relative_to(folder):
                return inside.relative_to(folder).as_posix()
        return str(path)

    def _issue(self, file: str, line: int | None, key: KeyPath | str, message: str) -> None:
        key_path = key if isinstance(key, str) else ".".join(str(k) for k in key)
        self.issues.append(RecipeIssue(file=file, line=line, key_path=key_path, message=message))

    # -- one file ------------------------------------------------------------------------------
    def _load_source(self, path: Path, display: str, *, extended: bool) -> Located | YamlSourceError:
        """The YAML of ``path`` with marks naming it ``display``.

        A file reached through ``extends`` is read once per :meth:`load_all` (presets are extended
        by many recipes); a recipe file itself is read when loaded and not kept.
        """
        key = Path(os.path.abspath(path))
        if extended and key in self._extended:
            return self._extended[key]
        try:
            own = load_located(path)
        except YamlSourceError as exc:
            source: Located | YamlSourceError = YamlSourceError(display, exc.line, str(exc))
        else:
            source = Located(own.data, {k: (display, line) for k, (_, line) in own.marks.items()})
        if extended:
            self._extended[key] = source
        return source

    def _resolve_extends(self, name: str, origin: Path) -> Path | str:
        """The file ``extends: name`` in ``origin`` means, or why it may not name it."""
        recipes = _real(self.workspace.recipes_dir)
        where = (
            "'extends' names a preset (a file of recipes/presets, by its name without .yaml) or a "
            ".yaml file inside recipes/, relative to the recipe"
        )
        if name.endswith((".yaml", ".yml")):
            if os.path.isabs(name) or name.startswith("~"):
                return f"{where}; {name!r} is an absolute path: write it relative to this recipe"
            path = _real(origin.parent / name)
        elif re.fullmatch(PRESET_NAME_PATTERN, name):
            path = _real(self.workspace.presets_dir / f"{name}.yaml")
        else:
            return f"{where}; {name!r} is neither"
        if not path.is_relative_to(recipes):
            return f"{where}; {name!r} leads outside recipes/ (to {path})"
        return path

    def _load_with_extends(self, path: Path, chain: tuple[Path, ...] = ()) -> Located | None:
        """``path`` merged over what it extends; ``chain`` holds the files extending it, outermost first."""
        display = self._relative(path)
        source = self._load_source(path, display, extended=bool(chain))
        path = _real(path)
        if isinstance(source, YamlSourceError):
            self._issue(source.file, source.line, "", str(source))
            return None
        if not isinstance(source.data, dict):
            self._issue(display, 1, "", "a recipe must be a mapping of keys to values")
            return None
        if not chain and isinstance(source.data.get("id"), str):
            self._own_id = source.data["id"]
        own = Located(dict(source.data), source.marks)
        parents = own.data.pop("extends", None)
        if parents is None:
            return own
        if isinstance(parents, str):
            parents = [parents]
        if not isinstance(parents, list) or not all(isinstance(p, str) for p in parents):
            self._issue(display, own.where(("extends",))[1], "extends", "'extends' takes a name or a list")
            return None
        merged = Located({}, {})
        for index, name in enumerate(parents):
            line = own.where(("extends", index) if len(parents) > 1 else ("extends",))[1]
            parent_path = self._resolve_extends(name, path)
            problem = self._extends_problem(name, parent_path, (*chain, path))
            if problem is not None:
                self._issue(display, line, "extends", problem)
                return None
            assert isinstance(parent_path, Path)
            parent = self._load_with_extends(parent_path, (*chain, path))
            if parent is None:
                return None
            merged = _merge(merged, parent)
        return _merge(merged, own)

    def _extends_problem(self, name: str, parent: Path | str, chain: tuple[Path, ...]) -> str | None:
        """Why ``extends: name`` (leading to ``parent``, from the files of ``chain``) cannot be followed."""
        if isinstance(parent, str):
            return parent
        if parent in chain:
            loop = " -> ".join(self._relative(p) for p in (*chain[chain.index(parent) :], parent))
            return f"'extends' forms a cycle: {loop}; remove one of these extends"
        self._followed += 1
        if self._followed > MAX_EXTENDS_FILES:
            return (
                f"'extends' reaches more than {MAX_EXTENDS_FILES} files (repeats counted); extend fewer files"
            )
        if not os.path.lexists(parent):
            known = sorted(p.stem for p in self.workspace.presets_dir.glob("*.yaml"))
            if known:
                return f"cannot extend {name!r}: {parent} does not exist; presets here: {', '.join(known)}"
            return (
                f"cannot extend {name!r}: this workspace ({self.workspace.root}) has no presets in "
                f"{self.workspace.presets_dir}: make a workspace with the shipped ones with `navverse init "
                "DIR`, or copy the project's recipes/presets/ here"
            )
        return None

    def _validate_params(
        self, located: Located, display: str, recipe_dir: Path, stages: dict[str, Any]
    ) -> list[StageCall]:
        calls: list[StageCall] = []
        for name in sorted(stages):
            section = dict(stages[name] or {})
            spec = self.stages.get(name)
            if spec is None:
                known = ", ".join(sorted(self.stages)) or "none registered"
                self._issue(
                    display,
                    located.where(("stages", name))[1],
                    ("stages", name),
                    f"unknown stage {name!r} (known stages: {known})",
                )
                continue
            skip = section.pop(SKIP_KEY, False)
            if not isinstance(skip, bool):
                self._issue(
                    display,
                    located.where(("stages", name, SKIP_KEY))[1],
                    ("stages", name, SKIP_KEY),
                    f"'{SKIP_KEY}' takes true or false (got {skip!r})",
                )
                continue
            if skip and not spec.skippable:
                self._issue(
                    display,
                    located.where(("stages", name, SKIP_KEY))[1],
                    ("stages", name, SKIP_KEY),
                    f"stage {name!r} cannot be skipped: nothing stands in for its outputs "
                    f"({', '.join(spec.outputs)}); remove the stage with '{name}: null' instead",
                )
                continue
            try:
                params = spec.params_model.model_validate(
                    section, context={"recipe_dir": recipe_dir, "workspace_root": self.workspace.root}
                )
            except (ImportError, SyntaxError) as exc:  # a validator's lazy import of a broken module
                raise StageImportError(f"a module the params of stage {name!r} need", exc) from None
            except ValidationError as exc:
                self._report(exc, located, ("stages", name), section, spec.params_model)
                continue
            calls.append(StageCall(spec=spec, params=params, skip=skip))
        return calls

    def _report(
        self,
        exc: ValidationError,
        located: Located,
        prefix: KeyPath,
        data: Any,
        model: type[BaseModel] | None,
    ) -> None:
        for error in exc.errors():
            loc = _existing_prefix(data, error["loc"], error["type"])
            path = (*prefix, *loc)
            file, line = located.where(path)
            message = error["msg"]
            if error["type"] == "extra_forbidden":
                known = _known_keys(model, loc[:-1])
                message = f"unknown key {loc[-1]!r}" + (f" (known keys: {', '.join(known)})" if known else "")
            elif error["type"] == "missing":
                message = "required key is missing"
            elif isinstance(error.get("input"), bool) and error["type"] == "int_type":
                message = (
                    f"{message} (got {error['input']}: yes/no/on/off/true/false are booleans in YAML; "
                    "write a number)"
                )
            elif "input" in error and error["type"] not in ("model_type", "dict_type"):
                message = f"{message} (got {_shown(error['input'])})"
            self._issue(file, line, path, message)

    def load_file(self, path: Path) -> list[Target]:
        """Validate one recipe file and expand it into targets; problems go to :attr:`issues`."""
        display = self._relative(path)
        self._followed = 0
        self._own_id = None
        located = self._load_with_extends(path)
        if located is None:
            return []
        data = located.data
        stages_raw = data.get("stages")
        top = dict(data)
        try:
            model = RecipeModel.model_validate(top)
        except ValidationError as exc:
            self._report(exc, located, (), top, RecipeModel)
            # still check stage params so that every problem is reported at once
            if isinstance(stages_raw, dict):
                stages_ok = {k: v for k, v in stages_raw.items() if v is None or isinstance(v, dict)}
                self._validate_params(located, display, path.parent, stages_ok)
            return []
        calls = self._validate_params(located, display, path.parent, model.stages)
        if len(calls) != len(model.stages):
            return []
        base_id = model.id or path.stem
        if not _matches_id(base_id):
            self._issue(display, 1, "id", f"target id {base_id!r} must match {TARGET_ID_PATTERN}; set 'id'")
            return []
        links = {
            name: Link(tuple(link), None)
            if isinstance(link, list)
            else Link(tuple(link.targets), link.artifact)
            for name, link in sorted(model.links.items())
        }
        expansions: list[tuple[str, int]]
        if model.seeds is not None:
            expansions = [(f"{base_id}-s{seed}", seed) for seed in model.seeds]
        elif model.count is not None:
            width = max(2, len(str(model.count - 1)))
            expansions = [(f"{base_id}-{i:0{width}d}", model.seed + i) for i in range(model.count)]
        else:
            expansions = [(base_id, model.seed)]
        hashed = _without_appearance(data, calls)
        targets = []
        for target_id, seed in expansions:
            recipe_hash = hash_value({"recipe": display, "data": hashed, "target": target_id, "seed": seed})
            targets.append(
                Target(
                    id=target_id,
                    recipe=display,
                    recipe_hash=recipe_hash,
                    seed=seed,
                    stages=tuple(calls),
                    links=links,
                    description=model.description,
                    manual=model.manual,
                )
            )
        return targets

    def load(self, files: Iterable[Path] | None = None) -> list[Target]:
        """Load ``files`` (default: every recipe) and raise one :class:`RecipeError` for all problems."""
        recipes = self.load_all(files)
        if recipes.broken:
            raise RecipeError(self.issues)
        return list(recipes.targets)

    def load_all(self, files: Iterable[Path] | None = None) -> RecipeSet:
        """Load ``files`` (default: every recipe), keeping the targets of the files without problems.

        A file with any problem (its own, one of a file it extends, or a target id another file
        already makes) contributes no target: it is listed in :attr:`RecipeSet.broken` with its
        problems, which :attr:`issues` holds too.
        """
        self.issues = []
        self._extended = {}
        targets: list[Target] = []
        broken: list[BrokenRecipe] = []
        seen: dict[str, str] = {}
        for path in self.recipe_files() if files is None else files:
            path = Path(path)
            start = len(self.issues)
            made = self.load_file(path)
            for target in made:
                if target.id in seen:
                    self._issue(
                        target.recipe,
                        None,
                        "id",
                        f"target id {target.id!r} is also made by {seen[target.id]}; give one an 'id'",
                    )
            if len(self.issues) > start:
                self._trim_issues(start)
                problems = tuple(self.issues[start:])
                base_id = self._own_id or path.stem  # as far as the file's own text tells
                broken.append(BrokenRecipe(self._relative(path), problems, base_id))
                continue
            for target in made:
                seen[target.id] = target.recipe
                targets.append(target)
        return RecipeSet(tuple(targets), tuple(broken))

    def _trim_issues(self, start: int) -> None:
        """Keep at most :data:`MAX_ISSUES_PER_FILE` of the problems found since ``start``."""
        found = self.issues[start:]
        if len(found) > MAX_ISSUES_PER_FILE:
            kept = found[: MAX_ISSUES_PER_FILE - 1]
            more = len(found) - len(kept)
            last = RecipeIssue(kept[-1].file, None, "", f"{more} more problems in this file are not listed")
            self.issues[start:] = [*kept, last]


def _matches_id(value: str) -> bool:
    return re.fullmatch(TARGET_ID_PATTERN, value) is not None


def _real(path: Path) -> Path:
    """``path`` absolute, with symbolic links resolved as far as they go (a loop stays a path)."""
    return Path(os.path.realpath(path))


_SHORT_REPR = reprlib.Repr()
_SHORT_REPR.maxstring = _SHORT_REPR.maxother = MAX_SHOWN_INPUT
_SHORT_REPR.maxlevel, _SHORT_REPR.maxlist, _SHORT_REPR.maxdict = 2, 4, 4


def _shown(value: Any) -> str:
    """``repr(value)``, shortened (a value quoted in a message stays short, however large it is)."""
    text = _SHORT_REPR.repr(value)  # bounded work on a large value
    return text if len(text) <= MAX_SHOWN_INPUT else f"{text[: MAX_SHOWN_INPUT - 3]}..."


def _existing_prefix(data: Any, loc: Sequence[str | int], error_type: str) -> tuple[str | int, ...]:
    """The part of a pydantic error location that names real keys (drops union/type tags)."""
    kept: list[str | int] = []
    node = data
    for index, part in enumerate(loc):
        in_dict = isinstance(node, dict) and part in node
        in_list = isinstance(node, list) and isinstance(part, int) and 0 <= part < len(node)
        if in_dict or in_list:
            kept.append(part)
            node = node[part]
        elif index == len(loc) - 1 and error_type in ("missing", "extra_forbidden"):
            kept.append(part)
        else:
            if error_type in ("missing", "extra_forbidden") and isinstance(part, str):
                continue
            break
    return tuple(kept)


def _known_keys(model: type[BaseModel] | None, loc: Sequence[str | int]) -> list[str]:
    """Field names of the (nested) model at ``loc``, when it can be found."""
    current: Any = model
    for part in loc:
        if isinstance(part, int):
            continue
        if not (isinstance(current, type) and issubclass(current, BaseModel)):
            return []
        field = current.model_fields.get(str(part))
        if field is None:
            return []
        current = _model_in(field.annotation)
    if isinstance(current, type) and issubclass(current, BaseModel):
        return sorted(current.model_fields)
    return []


def _model_in(annotation: Any) -> Any:
    """The first BaseModel class inside a (possibly generic) annotation."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in getattr(annotation, "__args__", ()) or ():
        found = _model_in(arg)
        if found is not None:
            return found
    return None


def _without_appearance(data: dict[str, Any], calls: Sequence[StageCall]) -> dict[str, Any]:
    """The recipe data without the sections of its appearance stages (what the recipe hash covers)."""
    looks = {call.spec.name for call in calls if call.spec.appearance}
    stages = data.get("stages")
    if not looks or not isinstance(stages, dict):
        return data
    return {**data, "stages": {name: section for name, section in stages.items() if name not in looks}}
