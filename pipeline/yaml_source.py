"""YAML loading that remembers where every key and item came from (file and line).

The loader is built for files nobody has checked: it reads only regular files of at most
:data:`MAX_FILE_BYTES`, only UTF-8 text, refuses nesting deeper than :data:`MAX_DEPTH`, and stops
expanding aliases once the document holds :data:`MAX_VALUES` values or :data:`MAX_TEXT_CHARS`
characters of text (an "alias bomb" of nested anchors is refused quickly, in bounded memory). Values
are the recipe language's only: text, integers within ±2**53, finite floats, booleans, null, lists and
mappings; YAML's other types (dates, binary, sets, custom tags) are refused with the line. Every
problem is a :class:`YamlSourceError` carrying the file and, when known, the line.
"""

from __future__ import annotations

import errno
import math
import os
import re
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from pipeline.params import file_kind

KeyPath = tuple[str | int, ...]

MAX_FILE_BYTES = 1 << 20
"""Largest recipe file read (1 MiB); a larger file is refused before it is read."""

MAX_DEPTH = 64
"""Deepest nesting of lists and mappings, in the text and after aliases are expanded."""

MAX_VALUES = 200_000
"""Most values (scalars, lists and mappings) a document may hold once its aliases are expanded."""

MAX_TEXT_CHARS = 8 << 20
"""Most characters of text (keys and scalar values) a document may hold once its aliases are expanded."""

MAX_INT = 2**53
"""Integers must lie within ±MAX_INT (they must survive a round trip through a float, as in JSON)."""

_TAG = "tag:yaml.org,2002:"
_STR, _INT, _FLOAT, _BOOL, _NULL = (f"{_TAG}{name}" for name in ("str", "int", "float", "bool", "null"))
_SEQ, _MAP, _MERGE, _VALUE = (f"{_TAG}{name}" for name in ("seq", "map", "merge", "value"))
_TIMESTAMP = f"{_TAG}timestamp"
_NULL_TEXT = frozenset({"", "~", "null", "Null", "NULL"})
_OVERFLOWING_NUMBER = re.compile(r"[-+]?[0-9]+(?:\.[0-9]*)?[eE][-+]?[0-9]+")
"""A plain number with an exponent and no sign after the 'e' or no dot: YAML 1.1 reads it as text,
but it is meant as a number; one beyond the float range is refused (as ``1e309``)."""
_INT_TEXT_LIMIT = 40
"""Characters of an integer's text beyond which it is too large without being parsed."""

_BOMS = {
    b"\xff\xfe\x00\x00": "UTF-32",
    b"\x00\x00\xfe\xff": "UTF-32",
    b"\xff\xfe": "UTF-16",
    b"\xfe\xff": "UTF-16",
}


@dataclass(frozen=True)
class Located:
    """A mapping/sequence tree loaded from YAML, with the source line of every key path.

    Attributes
    ----------
    data : Any
        Plain Python data (dicts, lists, str, int, float, bool, None).
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


class YamlSourceError(ValueError):
    """A file cannot be loaded as a recipe document: unreadable, not UTF-8, not YAML, too large or
    too deep, or holding a value recipes do not use. Carries the file and line (``None`` if unknown).
    """

    def __init__(self, file: str, line: int | None, message: str) -> None:
        self.file = file
        self.line = line
        super().__init__(message)


# -- reading ---------------------------------------------------------------------------------------


def read_text(path: Path, *, limit: int | None = None) -> str:
    """The UTF-8 text of the regular file ``path``, refusing anything else before reading it.

    Symbolic links are followed; what they lead to must be a regular file. Directories, named pipes,
    devices and sockets are refused without being opened for reading (a pipe would block), and so is
    a file larger than ``limit`` bytes (default :data:`MAX_FILE_BYTES`).

    Raises
    ------
    YamlSourceError
        If the file is missing, not a regular file, too large, unreadable or not UTF-8 text.
    """
    file = str(path)
    limit = MAX_FILE_BYTES if limit is None else limit
    try:
        info = os.stat(path)
    except OSError as exc:
        raise YamlSourceError(file, None, _stat_problem(path, exc)) from None
    _check_regular(file, info, limit)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
        with os.fdopen(fd, "rb") as handle:
            _check_regular(file, os.fstat(handle.fileno()), limit)  # the file may have been swapped
            data = handle.read(limit + 1)
    except OSError as exc:
        raise YamlSourceError(file, None, f"cannot be read: {exc.strerror or exc}") from None
    if len(data) > limit:
        raise YamlSourceError(file, None, _too_large(len(data), limit))
    return decode_text(data, file=file)


def _stat_problem(path: Path, exc: OSError) -> str:
    if exc.errno == errno.ELOOP:
        return "is a symbolic link loop (the link never reaches a file); point it at a recipe file"
    if exc.errno == errno.ENOENT and os.path.islink(path):
        return f"is a symbolic link to {os.readlink(path)!r}, which does not exist"
    if exc.errno == errno.ENOENT:
        return "file not found"
    return f"cannot be read: {exc.strerror}"


def _check_regular(file: str, info: os.stat_result, limit: int) -> None:
    mode = info.st_mode
    if not stat.S_ISREG(mode):
        kind = file_kind(mode)
        raise YamlSourceError(
            file, None, f"is {kind}, not a regular file; recipes are read from regular .yaml files only"
        )
    if info.st_size > limit:
        raise YamlSourceError(file, None, _too_large(info.st_size, limit))


def _too_large(size: int, limit: int) -> str:
    return (
        f"is too large ({size:,} bytes; recipe files are at most {limit:,} bytes): keep large data in "
        "a file that a stage reads, and name that file in the recipe"
    )


def decode_text(data: bytes, *, file: str) -> str:
    """``data`` decoded as UTF-8 (a UTF-8 byte-order mark is allowed), with a clear error otherwise."""
    for bom, encoding in _BOMS.items():
        if data.startswith(bom):
            raise YamlSourceError(
                file, 1, f"is {encoding} text (it starts with a {encoding} byte-order mark); save it as UTF-8"
            )
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise YamlSourceError(
            file,
            line,
            f"is not UTF-8 text (byte 0x{data[exc.start]:02x} cannot be decoded; Latin-1 or another "
            "encoding?): save the file as UTF-8",
        ) from None


# -- parsing ---------------------------------------------------------------------------------------


def load_located(path: Path) -> Located:
    """Load one YAML document from ``path`` with the line of every key and list item.

    Raises
    ------
    YamlSourceError
        If the file cannot be read (see :func:`read_text`), is not valid YAML, holds several
        documents, repeats a key in a mapping, nests too deep, expands past the limits, or holds a
        value recipes do not use.
    """
    return loads_located(read_text(path), file=str(path))


def loads_located(text: str, *, file: str) -> Located:
    """Like :func:`load_located`, from a string; ``file`` names it in messages."""
    node = _compose(text, file=file)
    if node is None:
        return Located({}, {(): (file, 1)})
    builder = _Builder(file)
    data = builder.build(node, (), depth=1)
    return Located(data, builder.marks)


class _AliasNode:
    """Where an alias is used (the composer otherwise hands back the anchored node itself)."""

    def __init__(self, target: yaml.Node, event: yaml.AliasEvent) -> None:
        self.target = target
        self.anchor = event.anchor
        self.line = event.start_mark.line + 1


class _BoundedComposer(yaml.composer.Composer, yaml.resolver.Resolver):
    """PyYAML's composer and resolver, refusing nesting deeper than :data:`MAX_DEPTH` and more than
    :data:`MAX_VALUES` nodes while it composes (so memory stays bounded), and keeping each alias's
    own position (:class:`_AliasNode`). Mixed into an event parser below."""

    def __init__(self, *, file: str) -> None:
        yaml.composer.Composer.__init__(self)
        yaml.resolver.Resolver.__init__(self)
        self.file = file
        self.depth = 0
        self.nodes = 0

    def compose_node(self, parent: yaml.Node | None, index: Any) -> Any:
        if self.check_event(yaml.AliasEvent):
            event = self.peek_event()
            return _AliasNode(super().compose_node(parent, index), event)
        nests = not self.check_event(yaml.ScalarEvent)  # a list or mapping
        self.depth += nests
        self.nodes += 1
        try:
            if self.depth > MAX_DEPTH or self.nodes > MAX_VALUES:
                line = self.peek_event().start_mark.line + 1
                raise YamlSourceError(self.file, line, _too_deep() if self.depth > MAX_DEPTH else _too_many())
            return super().compose_node(parent, index)
        finally:
            self.depth -= nests


class _PythonLoader(_BoundedComposer, yaml.reader.Reader, yaml.scanner.Scanner, yaml.parser.Parser):
    """The bounded composer over PyYAML's YAML parser written in Python."""

    def __init__(self, text: str, *, file: str) -> None:
        yaml.reader.Reader.__init__(self, text)
        yaml.scanner.Scanner.__init__(self)
        yaml.parser.Parser.__init__(self)
        _BoundedComposer.__init__(self, file=file)


try:
    from yaml._yaml import CParser
except ImportError:  # pragma: no cover - PyYAML built without libyaml
    _Loader: type = _PythonLoader
else:

    class _LibyamlLoader(_BoundedComposer, CParser):
        """The bounded composer over libyaml's parser (through PyYAML; some 25 times faster)."""

        def __init__(self, text: str, *, file: str) -> None:
            CParser.__init__(self, text)
            _BoundedComposer.__init__(self, file=file)

    _Loader = _LibyamlLoader


def _too_deep() -> str:
    return f"lists and mappings nest deeper than {MAX_DEPTH} levels; recipes nest at most {MAX_DEPTH} levels"


def _too_many(limit: str | None = None) -> str:
    limit = limit or f"{MAX_VALUES:,} values"
    return f"the recipe holds more than {limit}; keep large data in a file that a stage reads"


def _compose(text: str, *, file: str) -> yaml.Node | None:
    """The node graph of the single document in ``text`` (``None`` if empty)."""
    bad = yaml.reader.Reader.NON_PRINTABLE.search(text)
    if bad is not None:
        code = ord(bad.group())
        name = "NUL" if code == 0 else f"U+{code:04X}"
        hint = " (UTF-16 text looks like this: save it as UTF-8)" if code == 0 else ""
        raise YamlSourceError(
            file,
            text.count("\n", 0, bad.start()) + 1,
            f"holds the control character {name}, which YAML does not allow{hint}",
        )
    loader: _BoundedComposer | None = None
    try:
        loader = _Loader(text, file=file)
        return loader.get_single_node()
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        # libyaml marks an error at the end of the text on a line after the last one
        line = min(mark.line + 1, text.count("\n") + 1) if mark is not None else None
        what = " ".join(part for part in (exc.context, exc.problem) if part) or str(exc)
        if "maximum nesting depth" in what:  # libyaml's own limit (PyYAML >= 6.0.3), met before ours
            raise YamlSourceError(file, line, _too_deep()) from None
        raise YamlSourceError(file, line, f"invalid YAML: {what}") from None
    except yaml.YAMLError as exc:
        raise YamlSourceError(file, None, f"invalid YAML: {exc}") from None
    finally:
        if loader is not None:
            loader.dispose()


# -- building --------------------------------------------------------------------------------------


class _Builder:
    """Plain data and marks from a composed node graph, within the depth and expansion budgets."""

    def __init__(self, file: str) -> None:
        self.file = file
        self.marks: dict[KeyPath, tuple[str, int]] = {}
        self.values = 0
        self.chars = 0
        self.aliases: list[_AliasNode] = []  # the aliases being expanded, outermost first
        self.ancestors: set[int] = set()  # ids of the collection nodes being built
        self.constructor = yaml.constructor.SafeConstructor()

    def error(self, line: int | None, message: str) -> YamlSourceError:
        return YamlSourceError(self.file, line, message)

    def build(self, node: Any, path: KeyPath, *, depth: int) -> Any:
        if isinstance(node, _AliasNode):
            return self._build_alias(node, path, depth=depth)
        line = node.start_mark.line + 1
        self.marks[path] = (self.file, line)
        self._count(line, text=len(node.value) if isinstance(node, yaml.ScalarNode) else 0)
        if isinstance(node, yaml.ScalarNode):
            return self._scalar(node)
        if depth > MAX_DEPTH:
            raise self.error(self._outer_line(line), _too_deep() + " (with aliases and merge keys expanded)")
        self.ancestors.add(id(node))
        try:
            if isinstance(node, yaml.SequenceNode):
                self._check_tag(node, _SEQ, "a list")
                return [self.build(item, (*path, i), depth=depth + 1) for i, item in enumerate(node.value)]
            self._check_tag(node, _MAP, "a mapping")
            return self._mapping(node, path, depth=depth)
        finally:
            self.ancestors.discard(id(node))

    def _build_alias(self, alias: _AliasNode, path: KeyPath, *, depth: int) -> Any:
        if id(alias.target) in self.ancestors:
            raise self.error(
                alias.line,
                f"the alias *{alias.anchor} refers to a list or mapping that contains it "
                "(a structure without end); remove the alias",
            )
        self.aliases.append(alias)
        try:
            value = self.build(alias.target, path, depth=depth)
        finally:
            self.aliases.pop()
        self.marks[path] = (self.file, alias.line)
        return value

    def _count(self, line: int, *, text: int) -> None:
        self.values += 1
        self.chars += text
        if self.values <= MAX_VALUES and self.chars <= MAX_TEXT_CHARS:
            return
        limit = (
            f"{MAX_VALUES:,} values" if self.values > MAX_VALUES else f"{MAX_TEXT_CHARS:,} characters of text"
        )
        if self.aliases:
            outer = self.aliases[0]
            raise self.error(
                outer.line,
                f"the alias *{outer.anchor} expands the recipe past {limit}, the most a recipe may "
                "hold with its aliases expanded; use fewer (nested) aliases",
            )
        raise self.error(line, _too_many(limit))

    def _outer_line(self, line: int) -> int:
        return self.aliases[0].line if self.aliases else line

    def _check_tag(self, node: yaml.Node, expected: str, kind: str) -> None:
        if node.tag != expected:
            raise self.error(
                node.start_mark.line + 1,
                f"{_show_tag(node.tag)} ({kind}) is not a recipe value; recipes hold text, numbers, "
                "true/false, null, lists and mappings: remove the tag",
            )

    def _mapping(self, node: yaml.MappingNode, path: KeyPath, *, depth: int) -> dict[str, Any]:
        result: dict[str, Any] = {}
        merges: list[tuple[int, Any]] = []
        for key_node, value_node in node.value:
            key_line, key = self._key(key_node)
            if key is None:
                merges.append((key_line, value_node))
                continue
            if key in result:
                raise self.error(key_line, f"duplicate key {key!r}")
            child = (*path, key)
            result[key] = self.build(value_node, child, depth=depth + 1)
            self.marks[child] = (self.file, key_line)
        for key_line, value_node in merges:
            self._merge_into(result, key_line, value_node, path, depth=depth)
        return result

    def _key(self, key_node: Any) -> tuple[int, str | None]:
        """Line and text of a mapping key (``None`` for the merge key ``<<``).

        Keys are names: a scalar key keeps its source text, so ``on:`` or ``yes:`` stay the words
        they are rather than YAML 1.1 booleans.
        """
        line = key_node.line if isinstance(key_node, _AliasNode) else key_node.start_mark.line + 1
        target = key_node.target if isinstance(key_node, _AliasNode) else key_node
        if not isinstance(target, yaml.ScalarNode) or target.tag == _NULL:
            kind = "an empty (null) key" if isinstance(target, yaml.ScalarNode) else _kind(target)
            raise self.error(line, f"unsupported key: {kind}; keys are names (text)")
        self._count(line, text=len(target.value))
        if target.tag == _MERGE:
            return line, None
        return line, target.value

    def _merge_into(
        self, result: dict[str, Any], line: int, value_node: Any, path: KeyPath, *, depth: int
    ) -> None:
        """YAML's merge key: the entries of the merged mappings that the mapping does not set itself
        (among several merged mappings, the first one that sets a key wins)."""
        target = value_node.target if isinstance(value_node, _AliasNode) else value_node
        sources = target.value if isinstance(target, yaml.SequenceNode) else [value_node]
        for source in sources:
            source_target = source.target if isinstance(source, _AliasNode) else source
            if not isinstance(source_target, yaml.MappingNode):
                raise self.error(
                    line,
                    f"the merge key '<<' takes a mapping or a list of mappings (got {_kind(source_target)})",
                )
            own_marks, self.marks = self.marks, {}
            try:  # a merged mapping counts as a level: merges of merges nest
                merged = self.build(source, path, depth=depth + 1)
            finally:
                merged_marks, self.marks = self.marks, own_marks
            taken = {key for key in merged if key not in result}
            for key in taken:
                result[key] = merged[key]
            at = len(path)
            for mark_path, mark in merged_marks.items():
                if len(mark_path) > at and mark_path[at] in taken:
                    self.marks[mark_path] = mark

    def _scalar(self, node: yaml.ScalarNode) -> Any:
        tag, text, line = node.tag, node.value, node.start_mark.line + 1
        if tag in (_STR, _MERGE, _VALUE):  # a plain '<<' or '=' as a value is text
            if not node.style and _OVERFLOWING_NUMBER.fullmatch(text) and math.isinf(float(text)):
                raise self.error(line, _not_finite(text))
            return text
        if tag == _NULL and text in _NULL_TEXT:
            return None
        if tag == _BOOL and text.lower() in self.constructor.bool_values:
            return self.constructor.bool_values[text.lower()]
        if tag == _INT:
            return self._int(node, line)
        if tag == _FLOAT:
            return self._float(node, line)
        if tag == _TIMESTAMP:
            raise self.error(
                line,
                f"dates are not recipe values: quote it ({text!r}) to keep it as text",
            )
        if tag in (_NULL, _BOOL):
            raise self.error(line, f"{text!r} is not {_show_tag(tag)}; remove the tag or change the value")
        raise self.error(
            line,
            f"{_show_tag(tag)} is not a recipe value; recipes hold text, numbers, true/false, null, "
            "lists and mappings: remove the tag (quote the value to keep it as text)",
        )

    def _int(self, node: yaml.ScalarNode, line: int) -> int:
        text = node.value
        if len(text.replace("_", "")) > _INT_TEXT_LIMIT:
            raise self.error(line, _int_range(f"{text[:20]}... ({len(text)} characters)"))
        try:
            value = self.constructor.construct_yaml_int(node)
        except (ValueError, IndexError):
            raise self.error(line, f"{text!r} is not an integer") from None
        if abs(value) > MAX_INT:
            raise self.error(line, _int_range(text))
        return value

    def _float(self, node: yaml.ScalarNode, line: int) -> float:
        try:
            value = self.constructor.construct_yaml_float(node)
        except (ValueError, IndexError):
            raise self.error(line, f"{node.value!r} is not a number") from None
        if not math.isfinite(value):
            raise self.error(line, _not_finite(node.value))
        return value


def _not_finite(text: str) -> str:
    return (
        f"{text!r} is not a finite number (.nan, .inf and values beyond ±1.8e308 are not recipe "
        "values); write a finite number"
    )


def _int_range(shown: str) -> str:
    return f"the integer {shown} is out of range; recipe integers lie within ±2**53 ({MAX_INT:,})"


def _show_tag(tag: str) -> str:
    return f"!!{tag.removeprefix(_TAG)}" if tag.startswith(_TAG) else tag


def _kind(node: Any) -> str:
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.SequenceNode):
        return "a list"
    return f"the value {node.value[:40]!r}"
