"""Checks of an OpenStreetMap file before a parser opens it, and what osmium's errors mean.

:func:`check_osm_file` makes sure a file is a regular file of at most :data:`MAX_OSM_BYTES` whose
content matches its name (``.osm`` OSM XML, ``.osm.gz`` gzipped OSM XML, ``.osm.pbf`` PBF); an XML
file whose prolog holds a ``<!DOCTYPE`` (where entity declarations live, which can expand without
bound) is refused, and a plain ``.osm`` file that does not end with ``</osm>`` is reported as
truncated. What osmium still finds wrong while reading (a truncated PBF or gzip stream, malformed
XML) becomes a :class:`~navverse.city.map.CityMapError` naming the file (:func:`osmium_failure`).
"""

from __future__ import annotations

import gzip
import hashlib
import os
import re
import zlib
from collections.abc import Callable
from pathlib import Path

import osmium
import osmium.io
import osmium.osm

from navverse.city.map import CityMapError
from navverse.city.osm_window import LonLatBox
from navverse.files import regular_file_problem

__all__ = [
    "MAX_OSM_BYTES",
    "OSMIUM_ERRORS",
    "PROLOG_LIMIT",
    "Progress",
    "check_osm_file",
    "file_bounds",
    "file_sha256",
    "osmium_failure",
]

MAX_OSM_BYTES = 16 * 1024**3
"""Largest OSM file read (bytes): a large country's PBF; cut a smaller extract from anything larger."""
PROLOG_LIMIT = 64 * 1024
"""Bytes of an XML file scanned before its root element (XML declaration, comments)."""

Progress = Callable[[str, int], None]
"""``progress(phase, done)``: ``"checksum"`` with bytes hashed, ``"read"`` with OSM objects read."""

OSMIUM_ERRORS: tuple[type[Exception], ...] = (
    RuntimeError,
    ValueError,
    OSError,
    osmium.InvalidLocationError,
)
"""What osmium raises on bad input (libosmium's io, xml and pbf errors, ``illegal id: 'abc'``,
unreadable coordinates): each is turned into a :class:`CityMapError` naming the file."""

_SUFFIXES = ((".osm.pbf", "pbf"), (".osm.gz", "xml.gz"), (".osm", "xml"))
_CONTENT_NAMES = {
    "pbf": "PBF data (name it .osm.pbf)",
    "gzip": "gzip data (name it .osm.gz if it is gzipped OSM XML)",
    "xml": "XML (name it .osm if it is OSM XML)",
    "bzip2": "bzip2 data (unpack it with bunzip2 and read the .osm)",
}
_EXPECTED = {"pbf": "pbf", "xml.gz": "gzip", "xml": "xml"}
_NAMES = {"pbf": ".osm.pbf", "xml.gz": ".osm.gz", "xml": ".osm"}


def _content_kind(head: bytes) -> str:
    """What the first bytes of a file hold: pbf, gzip, bzip2, xml, empty or unknown."""
    if not head:
        return "empty"
    if head[:2] == b"\x1f\x8b":
        return "gzip"
    if head[:3] == b"BZh":
        return "bzip2"
    if len(head) >= 15 and head[4:15] == b"\x0a\x09OSMHeader":
        return "pbf"
    if head.removeprefix(b"\xef\xbb\xbf").lstrip(b" \t\r\n")[:1] == b"<":
        return "xml"
    return "unknown"


def _osm_format(path: Path) -> str:
    name = path.name.lower()
    for suffix, fmt in _SUFFIXES:
        if name.endswith(suffix):
            return fmt
    raise CityMapError(
        f"{path} is not named as an OSM file: use .osm (OSM XML), .osm.gz (gzipped OSM XML) or .osm.pbf"
    )


def _check_prolog(head: bytes, path: Path, *, complete: bool) -> None:
    """Refuse XML whose prolog declares a DOCTYPE, or whose root element is not ``<osm>``.

    Walks the prolog token by token (XML declaration, processing instructions, comments) up to the
    root element, so a DOCTYPE anywhere before it is found, and a prolog longer than the scanned
    bytes is refused rather than parsed blind.
    """
    text, i = head.removeprefix(b"\xef\xbb\xbf"), 0
    too_long = f"{path}: no <osm> root element in the first {PROLOG_LIMIT // 1024} KiB of XML"
    while True:
        while i < len(text) and text[i : i + 1] in b" \t\r\n":
            i += 1
        if i >= len(text):
            raise CityMapError(too_long if not complete else f"{path} holds no XML element: not OSM XML")
        if text.startswith(b"<?", i) or text.startswith(b"<!--", i):
            end_mark = b"?>" if text.startswith(b"<?", i) else b"-->"
            end = text.find(end_mark, i + 2)
            if end < 0:
                raise CityMapError(too_long if not complete else f"{path} ends inside its XML prolog")
            i = end + len(end_mark)
            continue
        if text.startswith(b"<!", i):
            raise CityMapError(
                f"{path} declares a <!DOCTYPE> (entity declarations can expand without bound): "
                "refused; OSM XML needs none, remove it"
            )
        match = re.match(rb"<([A-Za-z_][A-Za-z0-9_.:-]*)", text[i:])
        if match is None:
            raise CityMapError(f"{path} is not well-formed XML at byte {i}: not OSM XML")
        if match.group(1) != b"osm":
            root = match.group(1).decode("ascii", "replace")
            raise CityMapError(f"{path} is XML but not OSM XML: its root element is <{root}>, not <osm>")
        return


def _check_xml_end(path: Path, size: int) -> None:
    """Report a plain XML file that does not end with its root's end tag as truncated."""
    with open(path, "rb") as handle:
        handle.seek(max(0, size - 4096))
        tail = handle.read().rstrip()
    while tail.endswith(b"-->") and b"<!--" in tail:
        tail = tail[: tail.rfind(b"<!--")].rstrip()
    if not (tail.endswith(b"</osm>") or re.search(rb"<osm\b[^<>]*/>$", tail)):
        raise CityMapError(
            f"{path} ends before </osm>: the file is truncated (an interrupted download or copy?); "
            "fetch or export it again"
        )


def check_osm_file(path: str | os.PathLike[str]) -> str:
    """Check an OSM file before any parser opens it, and return its format.

    Parameters
    ----------
    path : path
        A ``.osm``, ``.osm.gz`` or ``.osm.pbf`` file.

    Returns
    -------
    str
        ``"xml"``, ``"xml.gz"`` or ``"pbf"``.

    Raises
    ------
    CityMapError
        If the file is missing, not a regular file, too large, empty, named for one format and holding
        another, truncated (plain XML: no ``</osm>`` at the end; gzip: ends within the first bytes),
        or XML with a DOCTYPE or a root other than ``<osm>``.
    """
    path = Path(path)
    problem = regular_file_problem(path, max_bytes=MAX_OSM_BYTES, what="OSM file")
    if problem:
        raise CityMapError(problem)
    fmt = _osm_format(path)
    with open(path, "rb") as handle:
        head = handle.read(PROLOG_LIMIT)
    kind = _content_kind(head)
    if kind == "empty":
        raise CityMapError(f"{path} is empty")
    if kind != _EXPECTED[fmt]:
        found = _CONTENT_NAMES.get(kind, "something that is neither OSM XML, gzip nor PBF")
        raise CityMapError(f"{path} is named {_NAMES[fmt]} but holds {found}")
    if fmt == "xml":
        _check_prolog(head, path, complete=len(head) < PROLOG_LIMIT)
        _check_xml_end(path, os.path.getsize(path))
    elif fmt == "xml.gz":
        try:
            with gzip.open(path, "rb") as handle:
                inner = handle.read(PROLOG_LIMIT)
        except (EOFError, OSError, zlib.error) as exc:
            raise CityMapError(
                f"{path} is a damaged or truncated gzip file ({exc}); fetch it again"
            ) from None
        if _content_kind(inner) != "xml":
            raise CityMapError(f"{path} is gzip, but what it holds is not OSM XML")
        _check_prolog(inner, path, complete=len(inner) < PROLOG_LIMIT)
    return fmt


def file_sha256(path: str | os.PathLike[str], *, progress: Progress | None = None) -> str:
    """The sha256 of a file, hex, read in 1 MiB chunks (``progress("checksum", bytes)`` per 64 MiB)."""
    digest, done = hashlib.sha256(), 0
    with open(path, "rb") as handle:
        while chunk := handle.read(1024 * 1024):
            digest.update(chunk)
            done += len(chunk)
            if progress is not None and done % (64 * 1024 * 1024) < len(chunk):
                progress("checksum", done)
    return digest.hexdigest()


def osmium_failure(path: Path, fmt: str, exc: Exception) -> CityMapError:
    """The :class:`CityMapError` for an error osmium raised reading ``path`` (of format ``fmt``)."""
    message = str(exc)
    lowered = message.lower()
    ends = ("eof", "truncated", "no element found", "unclosed token", "gzip error", "read close failed")
    what = {"pbf": "OSM PBF", "xml": "OSM XML", "xml.gz": "gzipped OSM XML"}[fmt]
    if any(word in lowered for word in ends):
        return CityMapError(
            f"{path} ends early or is damaged ({message}): the file is truncated or corrupt; "
            "fetch or export it again"
        )
    return CityMapError(f"{path} cannot be read as {what} ({message}): fix the file or export it again")


def file_bounds(path: str | os.PathLike[str], fmt: str) -> LonLatBox | None:
    """The data bounds the file's header declares (``<bounds>``, the PBF header bbox), or None."""
    try:
        reader = osmium.io.Reader(str(path), osmium.osm.NOTHING)
        try:
            box = reader.header().box()
        finally:
            reader.close()
    except OSMIUM_ERRORS as exc:
        raise osmium_failure(Path(path), fmt, exc) from None
    if not box.valid():
        return None
    low, high = box.bottom_left, box.top_right
    return (low.lon, low.lat, high.lon, high.lat)
