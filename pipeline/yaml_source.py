"""YAML loading that remembers where every key and item came from (file and line)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

KeyPath = tuple[str | int, ...]


@dataclass(frozen=True)
class Located:
    """A mapping/sequence tree loaded from YAML, with the source line of every key path.

    Attributes
    ----------
    data : Any
        Plain Python data (dicts, lists, scalars).
    marks : dict
        ``{key_path: (file, line)}``; the empty path maps to the document itself.
    """

    data: Any
    marks: dict[KeyPath, tuple[str, int]] = field(default_factory=dict)

    def where(self, path: KeyPath) -> tuple[str, int | None]:
        """File and line of ``path``, or of its nearest ancestor that has one."""
        for end in range(len(path), -1, -1):
            mark = self.marks.get(tuple(path[:end]))
            if mark is not None:
                return mark
        return ("<unknown>", None)


class YamlSyntaxError(ValueError):
    """The text is not valid YAML (or has duplicate keys); carries file and line."""

    def __init__(self, file: str, line: int | None, message: str) -> None:
        self.file = file
        self.line = line
        super().__init__(message)


def load_located(path: Path) -> Located:
    """Load one YAML document from ``path`` with the line of every key and list item.

    Raises
    ------
    YamlSyntaxError
        If the file is not valid YAML, holds several documents, or repeats a key in a mapping.
    """
    text = path.read_text(encoding="utf-8")
    return loads_located(text, file=str(path))


def loads_located(text: str, *, file: str) -> Located:
    """Like :func:`load_located`, from a string; ``file`` names it in messages."""
    loader = yaml.SafeLoader(text)
    try:
        node = loader.get_single_node()
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else None
        raise YamlSyntaxError(file, line, f"invalid YAML: {exc.problem or exc}") from None
    except yaml.YAMLError as exc:
        raise YamlSyntaxError(file, None, f"invalid YAML: {exc}") from None
    finally:
        loader.dispose()
    if node is None:
        return Located({}, {(): (file, 1)})
    marks: dict[KeyPath, tuple[str, int]] = {}
    constructor = yaml.SafeLoader("")
    data = _build(node, (), file, marks, constructor)
    return Located(data, marks)


def _build(
    node: yaml.Node,
    path: KeyPath,
    file: str,
    marks: dict[KeyPath, tuple[str, int]],
    constructor: yaml.SafeLoader,
) -> Any:
    marks[path] = (file, node.start_mark.line + 1)
    if isinstance(node, yaml.MappingNode):
        constructor.flatten_mapping(node)
        result: dict[Any, Any] = {}
        for key_node, value_node in node.value:
            # Keys are names: keep a scalar key's source text, so `on:` or `yes:` stay the words
            # they are rather than YAML 1.1 booleans.
            if not isinstance(key_node, yaml.ScalarNode) or key_node.tag == "tag:yaml.org,2002:null":
                shown = constructor.construct_object(key_node, deep=True)
                raise YamlSyntaxError(file, key_node.start_mark.line + 1, f"unsupported key {shown!r}")
            key = key_node.value
            if key in result:
                raise YamlSyntaxError(file, key_node.start_mark.line + 1, f"duplicate key {key!r}")
            child = (*path, key)
            result[key] = _build(value_node, child, file, marks, constructor)
            marks[child] = (file, key_node.start_mark.line + 1)
        return result
    if isinstance(node, yaml.SequenceNode):
        return [_build(item, (*path, i), file, marks, constructor) for i, item in enumerate(node.value)]
    return constructor.construct_object(node, deep=True)
