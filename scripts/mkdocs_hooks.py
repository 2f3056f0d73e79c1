"""MkDocs hooks of the NavVerse site (``hooks:`` in ``mkdocs.yml``): the pages generated from the code.

A page asks for generated text with a marker on a line of its own:

- ``<!-- generated: stage-reference -->`` becomes the stage parameter reference,
  :func:`stage_reference`: one section per registered stage (``pipeline.stage.discover("stages")``)
  with its one-line doc, inputs, outputs and a table of its parameters, read from its params model
  (type, default, bounds from the ``annotated_types`` constraints, description from the attribute
  docstring), and a table for each model nested in it;
- ``<!-- generated: metrics -->`` becomes the metric definitions, :func:`metrics_reference`: every
  public metric of ``navverse.eval.metrics.METRICS`` with its full name, abbreviation, definition,
  formula (LaTeX, rendered by MathJax when the page is viewed), unit and reference;
- ``<!-- generated: statistics -->`` becomes the group statistics of ``STATISTICS`` (label shares,
  failure counts), :func:`statistics_reference`, laid out the same way.

The hook also adds ``javascripts/mathjax.js`` (the MathJax settings for ``pymdownx.arithmatex``) and
``stylesheets/extra.css``.
Nothing is fetched while the site is built. An unknown marker stops the build.
"""

from __future__ import annotations

import functools
import inspect
import json
import re
import sys
import types
import typing
from collections import abc
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

import annotated_types
import griffe
import yaml
from pydantic import BaseModel
from pydantic.fields import FieldInfo

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # the project's packages, when mkdocs runs outside the editable install
    sys.path.insert(0, str(ROOT))

MARKER = re.compile(r"^<!-- generated: ([a-z-]+) -->$", re.MULTILINE)
"""A line asking for generated text."""

MATHJAX_JS = """\
// MathJax settings for pymdownx.arithmatex (generic mode): \\( ... \\) inline, \\[ ... \\] displayed.
window.MathJax = {
  tex: {inlineMath: [["\\\\(", "\\\\)"]], displayMath: [["\\\\[", "\\\\]"]], processEscapes: true},
  options: {ignoreHtmlClass: ".*|", processHtmlClass: "arithmatex"},
};
document$.subscribe(() => {
  if (window.MathJax && MathJax.typesetPromise) {
    MathJax.startup.output.clearCache();
    MathJax.typesetClear();
    MathJax.texReset();
    MathJax.typesetPromise();
  }
});
"""


EXTRA_CSS = """\
/* Parameter and metric names in the first column of a table are not broken inside a word. */
.md-typeset td:first-child code { white-space: nowrap; word-break: keep-all; }
"""


# ------------------------------------------------------------------------------------------ text


_ROLE = re.compile(r":[a-z]+:`~?([^`]+)`")


def markdown_text(text: str) -> str:
    """Docstring text (reStructuredText roles and literals) as one line of Markdown.

    ``:func:`~a.b.c``` becomes ```c```, ``:class:`a.B``` becomes ```a.B```, a double-backquoted
    literal becomes a code span; lines are joined.
    """
    text = " ".join(line.strip() for line in text.strip().splitlines())

    def role(match: re.Match[str]) -> str:
        target = match.group(0)
        name = re.sub(r"\s+", "", match.group(1))
        shown = name.rsplit(".", 1)[-1] if ":`~" in target else name
        return f"`{shown}`"

    text = _ROLE.sub(role, text)
    return escape_html(re.sub(r"``(.+?)``", r"`\1`", text))


_CODE_SPAN = re.compile(r"(`+)(.+?)\1")


def escape_html(text: str) -> str:
    """``<``, ``>`` and ``&`` outside code spans as entities, so ``<name>/v<version>`` stays text."""
    parts, last = [], 0
    for match in _CODE_SPAN.finditer(text):
        parts += [_entities(text[last : match.start()]), match.group(0)]
        last = match.end()
    return "".join([*parts, _entities(text[last:])])


def _entities(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def paragraphs(doc: str) -> list[str]:
    """The paragraphs of a docstring, each as one line of Markdown."""
    return [markdown_text(block) for block in re.split(r"\n\s*\n", inspect.cleandoc(doc)) if block.strip()]


def cell(text: str) -> str:
    """Text for a Markdown table cell: pipes escaped, on one line."""
    return " ".join(text.split()).replace("|", "\\|")


def code(text: str) -> str:
    """A code span holding ``text`` (longer fences when it holds backquotes)."""
    fence = "``" if "`" in text else "`"
    pad = " " if text.startswith("`") or text.endswith("`") else ""
    return f"{fence}{pad}{text}{pad}{fence}"


# ------------------------------------------------------------------------------------------ types


def _unwrap(tp: Any) -> tuple[Any, list[Any]]:
    """A type without ``Annotated``, and the metadata it carried (a nested FieldInfo's too)."""
    metadata: list[Any] = []
    while typing.get_origin(tp) is typing.Annotated:
        tp, *extra = typing.get_args(tp)
        for item in extra:
            if isinstance(item, FieldInfo):
                metadata.extend(item.metadata)
            else:
                metadata.append(item)
    return tp, metadata


def _is_model(tp: Any) -> bool:
    return isinstance(tp, type) and issubclass(tp, BaseModel)


def _is_union(tp: Any) -> bool:
    return typing.get_origin(tp) in (typing.Union, types.UnionType)


def type_text(tp: Any) -> str:
    """A field's type as a recipe author reads it: ``float``, ``[float, float]``, ``list[str]``..."""
    tp, _ = _unwrap(tp)
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if tp is type(None):
        return "null"
    if _is_union(tp):
        ordered = [a for a in args if a is not type(None)] + [a for a in args if a is type(None)]
        return " or ".join(type_text(a) for a in ordered)
    if origin is typing.Literal:
        return " or ".join(json.dumps(a) if isinstance(a, str) else str(a) for a in args)
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return f"list[{type_text(args[0])}]"
        return "[" + ", ".join(type_text(a) for a in args) + "]"
    if origin in (list, set, frozenset, abc.Sequence, abc.Set):
        return f"list[{type_text(args[0])}]" if args else "list"
    if origin in (dict, abc.Mapping):
        return f"dict[{type_text(args[0])}, {type_text(args[1])}]" if args else "dict"
    if isinstance(tp, type) and issubclass(tp, Path):
        return "path"
    if isinstance(tp, type):
        return tp.__name__
    return str(tp).replace("typing.", "")


def nested_models(tp: Any) -> list[type[BaseModel]]:
    """The pydantic models a type refers to (in a list, a dict, an optional...), in order."""
    tp, _ = _unwrap(tp)
    if _is_model(tp):
        return [tp]
    found: list[type[BaseModel]] = []
    for arg in typing.get_args(tp):
        for model in nested_models(arg):
            if model not in found:
                found.append(model)
    return found


# ------------------------------------------------------------------------------------------ bounds


def _number(value: Any) -> str:
    """A bound as written in a recipe: ``0``, ``0.05``, ``1e7``, ``1e-06``."""
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e15:
        value = int(value)
    if isinstance(value, int) and abs(value) >= 100_000 and value % 1000 == 0:
        return f"{value:.0e}".replace("e+0", "e").replace("e+", "e")
    return f"{value:g}" if isinstance(value, float) else str(value)


def _interval(metadata: Iterable[Any]) -> str:
    """The numeric range the constraints allow: ``[0, 200]``, ``(0, 50]``, ``≥ 1``; '' for none."""
    low = high = None
    low_open = high_open = False
    for item in metadata:
        if isinstance(item, annotated_types.Ge):
            low, low_open = item.ge, False
        elif isinstance(item, annotated_types.Gt):
            low, low_open = item.gt, True
        elif isinstance(item, annotated_types.Le):
            high, high_open = item.le, False
        elif isinstance(item, annotated_types.Lt):
            high, high_open = item.lt, True
        elif isinstance(item, annotated_types.Interval):
            return _interval(
                [annotated_types.Ge(item.ge)] * (item.ge is not None)
                + [annotated_types.Gt(item.gt)] * (item.gt is not None)
                + [annotated_types.Le(item.le)] * (item.le is not None)
                + [annotated_types.Lt(item.lt)] * (item.lt is not None)
            )
    if low is not None and high is not None:
        return f"{'(' if low_open else '['}{_number(low)}, {_number(high)}{')' if high_open else ']'}"
    if low is not None:
        return f"{'>' if low_open else '≥'} {_number(low)}"
    if high is not None:
        return f"{'<' if high_open else '≤'} {_number(high)}"
    return ""


def _length(metadata: Iterable[Any]) -> str:
    low = high = None
    for item in metadata:
        if isinstance(item, annotated_types.MinLen):
            low = item.min_length
        elif isinstance(item, annotated_types.MaxLen):
            high = item.max_length
    if low and high is not None:
        return f"{_number(low)} to {_number(high)} items"
    if low:
        return f"at least {_number(low)} items"
    if high is not None:
        return f"at most {_number(high)} items"
    return ""


def _pattern(metadata: Iterable[Any]) -> str:
    for item in metadata:
        pattern = getattr(item, "pattern", None)
        if isinstance(pattern, str):
            return f"matches {code(pattern)}"
    return ""


def bounds_text(tp: Any, metadata: Iterable[Any] = ()) -> str:
    """What values a field allows beyond its type: ranges of numbers (of each element of a pair, of a
    list's items, of a dict's values), list lengths and text patterns."""
    tp, inner = _unwrap(tp)
    metadata = [*metadata, *inner]
    parts = [p for p in (_interval(metadata), _length(metadata), _pattern(metadata)) if p]
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if _is_union(tp):
        parts += [b for b in (bounds_text(a) for a in args if a is not type(None)) if b]
    elif origin is tuple and args and not (len(args) == 2 and args[1] is Ellipsis):
        each = [bounds_text(a) for a in args]
        if any(each):
            if len(set(each)) == 1:
                parts.append(_inner("each", each[0]))
            else:
                parts.append("; ".join(_inner(_ordinal(i), b or "any") for i, b in enumerate(each)))
    elif origin in (list, set, frozenset, abc.Sequence, abc.Set) or (origin is tuple and args):
        item = bounds_text(args[0]) if args else ""
        if item:
            parts.append(_inner("items", item))
    elif origin in (dict, abc.Mapping) and len(args) == 2:
        value = bounds_text(args[1])
        if value:
            parts.append(_inner("values", value))
    return "; ".join(parts)


def _inner(label: str, text: str) -> str:
    """``label: text``, once: the values of a dict of dicts are ``values: [1, 10]``."""
    return text if text.startswith(("each:", "items:", "values:")) else f"{label}: {text}"


def _ordinal(index: int) -> str:
    return ("1st", "2nd", "3rd")[index] if index < 3 else f"{index + 1}th"


# ------------------------------------------------------------------------------------------ defaults


def _plain(value: Any) -> Any:
    if isinstance(value, BaseModel):
        return {k: _plain(v) for k, v in value.model_dump(exclude_defaults=True).items()}
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, set, frozenset)):
        return [_plain(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    if hasattr(value, "value") and not isinstance(value, (int, float, str)):  # an enum member
        return _plain(value.value)
    return value


def default_text(field: FieldInfo) -> str:
    """A field's default as a recipe writes it (YAML flow style), or ``required``."""
    if field.is_required():
        return "required"
    value = _plain(field.get_default(call_default_factory=True))
    text = yaml.safe_dump(value, default_flow_style=True, width=10_000, allow_unicode=True).strip()
    return text.removesuffix("...").strip()


# ------------------------------------------------------------------------------------------ stages


def _model_table(model: type[BaseModel]) -> list[str]:
    lines = ["| parameter | type | default | bounds | description |", "|---|---|---|---|---|"]
    for name, field in model.model_fields.items():
        lines.append(
            "| "
            + " | ".join(
                (
                    code(name),
                    code(type_text(field.annotation)),
                    code(default_text(field)),
                    cell(bounds_text(field.annotation, field.metadata)),
                    cell(markdown_text(field.description or "")) or "—",
                )
            )
            + " |"
        )
    return lines


def _nested_tree(model: type[BaseModel]) -> dict[type[BaseModel], list[str]]:
    """The models nested in ``model``'s fields, at any depth, breadth first: ``{model: [where]}``, where
    a place is a field of ``model`` (``surfaces``) or of a nested model (``SurfaceSolid.ramp``)."""
    found: dict[type[BaseModel], list[str]] = {}
    queue: list[type[BaseModel]] = [model]
    while queue:
        parent = queue.pop(0)
        for name, field in parent.model_fields.items():
            for nested in nested_models(field.annotation):
                if nested is model:
                    continue
                place = name if parent is model else f"{parent.__name__}.{name}"
                if nested not in found:
                    found[nested] = []
                    queue.append(nested)
                found[nested].append(place)
    return found


def _inputs_text(spec: Any) -> str:
    if not spec.inputs:
        return "nothing (a first stage)"
    words = []
    for item in spec.inputs:
        text = code(item.name)
        if item.source != item.name:
            text += f" (artifact {code(item.source)})"
        if item.many:
            text += ", of the targets named in `links`"
        words.append(text)
    return "; ".join(words)


def _stage_section(name: str, spec: Any) -> list[str]:
    model = spec.params_model
    lines = [f"### `{name}` {{#stage-{name}}}", "", _stage_doc(spec), ""]
    lines.append(f"- **Reads:** {_inputs_text(spec)}")
    lines.append(f"- **Writes:** {', '.join(code(o) for o in spec.outputs)}")
    if spec.passthrough:
        through = ", ".join(f"{code(i)} as {code(o)}" for o, i in spec.passthrough.items())
        lines.append(f"- **Skippable:** `{name}: {{skip: true}}` passes {through} through unchanged")
    lines.append(f"- **Params model:** `{model.__module__}.{model.__qualname__}`")
    lines.append("")
    doc = model.__doc__ or ""
    if doc.strip():
        lines += [*(p + "\n" for p in paragraphs(doc))]
    if model.model_fields:
        lines += _model_table(model)
    else:
        lines.append("No parameters: `{}`.")
    lines.append("")
    for nested, places in _nested_tree(model).items():
        lines.append(f"**{code(nested.__name__)}**, used in {', '.join(code(p) for p in places)}:")
        lines.append("")
        lines += _model_table(nested)
        lines.append("")
    return lines


def _stage_doc(spec: Any) -> str:
    """What a stage produces: its one-line doc (``spec.doc``), completed to the end of the first
    paragraph of its docstring when that line wraps."""
    first = paragraphs(inspect.getdoc(spec.fn) or "")[:1]
    flat = " ".join(spec.doc.split())
    return (
        first[0]
        if first and " ".join(first[0].split()).startswith(markdown_text(flat))
        else markdown_text(flat)
    )


@functools.cache
def stages() -> dict[str, Any]:
    """The stages of the ``stages`` package, ``{name: StageSpec}``, sorted by name (stages registered by
    other modules of the same process, such as tests' toy stages, are left out)."""
    from pipeline.stage import discover

    registry = sorted(discover("stages").items())
    return {name: spec for name, spec in registry if spec.module.startswith("stages.")}


def stage_reference(registry: Mapping[str, Any] | None = None) -> str:
    """The stage parameter reference (Markdown): a summary table, then a section per stage."""
    registry = stages() if registry is None else registry
    lines = ["| stage | reads | writes | what it produces |", "|---|---|---|---|"]
    for name, spec in registry.items():
        reads = ", ".join(code(i.name) for i in spec.inputs) or "—"
        writes = ", ".join(code(o) for o in spec.outputs)
        lines.append(f"| [`{name}`](#stage-{name}) | {reads} | {writes} | {cell(markdown_text(spec.doc))} |")
    lines.append("")
    for name, spec in registry.items():
        lines += _stage_section(name, spec)
    return "\n".join(lines)


# ------------------------------------------------------------------------------------------ metrics


def public_metrics(registry: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The metrics a submission is scored with: the registry's entries not named ``_...``."""
    if registry is None:
        from navverse.eval import metrics

        registry = metrics.METRICS
    return {name: m for name, m in registry.items() if not name.startswith("_")}


def _applies(metric: Any) -> str:
    """The episodes a metric is defined on: ``every task, `i2o` scenes``."""
    tasks = ", ".join(code(t) for t in metric.tasks) if metric.tasks else "every task"
    kinds = (
        f"{', '.join(code(k) for k in metric.scene_types)} scenes"
        if metric.scene_types
        else "every scene type"
    )
    return f"{tasks}, {kinds}"


def _better(entry: Any) -> str:
    return "higher" if entry.higher_is_better else "lower"


def _definitions(entries: Mapping[str, Any], anchor: str, *, applies: bool) -> list[str]:
    """A summary table, then a section per entry: its title and abbreviation, definition, formula
    (displayed LaTeX), key, unit, direction, the episodes it is defined on and its reference."""
    columns = ["name", "abbreviation", "key", "unit", "better", *(["defined for"] if applies else [])]
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for name, entry in entries.items():
        row = [
            f"[{cell(entry.title)}](#{anchor}-{name})",
            cell(entry.abbreviation),
            code(name),
            cell(entry.unit) or "—",
            _better(entry),
            *([cell(_applies(entry))] if applies else []),
        ]
        lines.append("| " + " | ".join(row) + " |")
    lines.append("")
    for name, entry in entries.items():
        title, abbreviation = escape_html(entry.title), escape_html(entry.abbreviation)
        lines += [f"### {title} ({abbreviation}) {{#{anchor}-{name}}}", ""]
        lines += [markdown_text(entry.description), ""]
        lines += ["$$", entry.formula.strip(), "$$", ""]
        facts = [
            f"key {code(name)}",
            f"unit {entry.unit}" if entry.unit else "a count",
            f"{_better(entry)} is better",
        ]
        if applies:
            facts.append(f"defined for {_applies(entry)}")
        lines.append("- " + "; ".join(facts))
        if entry.reference:
            lines.append(f"- In the paper: {markdown_text(entry.reference)}")
        lines.append("")
    return lines


def metrics_reference(registry: Mapping[str, Any] | None = None) -> str:
    """The metric definitions (Markdown) of ``navverse.eval.metrics.METRICS`` (or ``registry``): a summary
    table, then a section per public metric with its formula."""
    return "\n".join(_definitions(public_metrics(registry), "metric", applies=True))


def statistics_reference(registry: Mapping[str, Any] | None = None) -> str:
    """The group statistics (Markdown) of ``navverse.eval.metrics.STATISTICS`` (or ``registry``): the
    numbers per group of episodes that are not means of a metric (label shares, failure counts)."""
    if registry is None:
        from navverse.eval import metrics

        registry = metrics.STATISTICS
    return "\n".join(_definitions(dict(registry), "statistic", applies=False))


# ------------------------------------------------------------------------------------------ docstrings


def rst_to_markdown(text: str) -> str:
    """A numpydoc docstring's reStructuredText roles and literal-block markers, for Markdown.

    ``:func:`~a.b.c``` becomes ```c```, ``:class:`a.B``` becomes ```a.B``` (code spans, not links, so
    a reference to an object the site does not document is no broken link), and a paragraph ending in
    ``::`` ends in ``:`` (its indented block is a code block in Markdown too).
    """

    def role(match: re.Match[str]) -> str:
        name = re.sub(r"\s+", "", match.group(1))
        return f"`{name.rsplit('.', 1)[-1] if ':`~' in match.group(0) else name}`"

    text = _ROLE.sub(role, text)
    return re.sub(r"(\S)::$", r"\1:", text, flags=re.MULTILINE)


class RstRoles(griffe.Extension):
    """A griffe extension (``extensions:`` of the mkdocstrings python handler) applying
    :func:`rst_to_markdown` to every docstring the API pages render."""

    def on_instance(self, *, obj: griffe.Object, **_: Any) -> None:
        if obj.docstring is not None:
            obj.docstring.value = rst_to_markdown(obj.docstring.value)


GENERATORS: dict[str, Callable[[], str]] = {
    "stage-reference": stage_reference,
    "metrics": metrics_reference,
    "statistics": statistics_reference,
}
"""The markers a page may hold, and what replaces each."""


# ------------------------------------------------------------------------------------------ hooks


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any, **_: Any) -> str:
    """Replace each ``<!-- generated: NAME -->`` line of a page with the text of ``GENERATORS[NAME]``."""

    def generate(match: re.Match[str]) -> str:
        name = match.group(1)
        if name not in GENERATORS:
            from mkdocs.exceptions import PluginError

            raise PluginError(f"{page.file.src_uri}: unknown marker {name!r}; known: {', '.join(GENERATORS)}")
        return GENERATORS[name]()

    return MARKER.sub(generate, markdown)


def on_files(files: Any, config: Any, **_: Any) -> Any:
    """Add ``javascripts/mathjax.js`` (the MathJax settings) and ``stylesheets/extra.css`` to the site."""
    from mkdocs.structure.files import File

    files.append(File.generated(config, "javascripts/mathjax.js", content=MATHJAX_JS))
    files.append(File.generated(config, "stylesheets/extra.css", content=EXTRA_CSS))
    return files
