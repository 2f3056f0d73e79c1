"""Checks of an OpenStreetMap file before a parser opens it, and what osmium's errors mean.

:func:`check_osm_file` makes sure a file is a regular file of at most :data:`MAX_OSM_BYTES` holding
OSM XML, gzipped or bzip2-compressed OSM XML, or PBF, recognised by its first bytes whatever its name
(``.osm.xml.gz`` as Overpass names it, a link named anything), and measures how much data it holds
once decompressed, without parsing it. osmium is then told the format (:func:`osmium_file`):

- XML: an XML file whose prolog holds a ``<!DOCTYPE`` (where entity declarations live, which can
  expand without bound) is refused, and one that does not end with ``</osm>`` is truncated;
- gzip and bzip2: the file is decompressed once as a stream (constant memory) to check the same of the XML it
  holds, to find a truncated stream, and to refuse a decompression bomb (more than
  :data:`MAX_OSM_BYTES` of XML, or more than :data:`MAX_RATIO` times the file's size);
- PBF: the blob headers are walked (no decompression) to find a truncated or malformed file and
  to sum the blobs' decompressed sizes, with the same bomb limits.

What osmium still finds wrong while reading (malformed XML, bad ids or coordinates, damaged blobs)
becomes a :class:`~navverse.city.map.CityMapError` naming the file (:func:`osmium_failure`).
"""

from __future__ import annotations

import bz2
import io
import math
import os
import re
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import IO

import numpy as np
import osmium
import osmium.io
import osmium.osm

from navverse.city.map import CityMapError
from navverse.city.osm.window import LonLatBox
from navverse.files import regular_file_problem

__all__ = [
    "ACCEPTED",
    "MAX_OSM_BYTES",
    "MAX_RATIO",
    "OSMIUM_ERRORS",
    "OSMIUM_FORMATS",
    "PROLOG_LIMIT",
    "OsmFile",
    "Progress",
    "check_osm_file",
    "file_bounds",
    "osmium_failure",
    "osmium_file",
]

MAX_OSM_BYTES = 16 * 1024**3
"""Largest OSM file read (bytes): a large country's PBF; cut a smaller extract from anything larger."""
PROLOG_LIMIT = 64 * 1024
"""Bytes of an XML file scanned before its root element (XML declaration, comments)."""
MAX_RATIO = 100
"""Most data a compressed file may decompress to, per byte, once past :data:`_RATIO_FREE` bytes:
OSM XML gzips about 10:1 and PBF blobs 3:1; far more is a decompression bomb."""
_RATIO_FREE = 64 * 1024**2
_CHUNK = 1024 * 1024
_TAIL = 4096
_MAX_BLOB_HEADER = 64 * 1024
_MAX_BLOB = 32 * 1024**2

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

_FORMATS = {"pbf": "pbf", "gzip": "xml.gz", "bzip2": "xml.bz2", "xml": "xml"}
"""The format of an OSM file by the kind of its first bytes: its name does not decide."""
OSMIUM_FORMATS = {"pbf": "pbf", "xml": "osm", "xml.gz": "osm.gz", "xml.bz2": "osm.bz2"}
"""The format osmium is told for each format, so that it never guesses from the file's name (a link
or a download may be named anything)."""
ACCEPTED = (
    "OSM XML (.osm, .osm.xml), gzipped or bzip2-compressed OSM XML (.osm.gz, .osm.bz2) or PBF (.osm.pbf)"
)
"""What :func:`check_osm_file` reads, as its messages name it."""


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


def _check_xml_tail(tail: bytes, path: Path) -> None:
    """Report XML whose last bytes are not its root's end tag (comments may follow) as truncated."""
    tail = tail.rstrip()
    while tail.endswith(b"-->") and b"<!--" in tail:
        tail = tail[: tail.rfind(b"<!--")].rstrip()
    if not (tail.endswith(b"</osm>") or re.search(rb"<osm\b[^<>]*/>$", tail)):
        raise CityMapError(
            f"{path} ends before </osm>: the file is truncated (an interrupted download or copy?); "
            "fetch or export it again"
        )


def _bomb(path: Path, size: int, compressed: int) -> CityMapError | None:
    if size > MAX_OSM_BYTES or (size > _RATIO_FREE and size > MAX_RATIO * compressed):
        return CityMapError(
            f"{path} decompresses to more than {min(size, MAX_OSM_BYTES) / 1024**2:.0f} MiB from "
            f"{compressed / 1024**2:.1f} MiB (over {MAX_RATIO}:1 or {MAX_OSM_BYTES / 1024**3:.0f} GiB): "
            "refused as a decompression bomb; cut a smaller extract"
        )
    return None


def _decompressor(fmt: str):
    """A fresh stream decompressor for one member of a ``xml.gz`` or ``xml.bz2`` file."""
    return zlib.decompressobj(zlib.MAX_WBITS | 16) if fmt == "xml.gz" else bz2.BZ2Decompressor()


_MAGIC = {"xml.gz": b"\x1f\x8b", "xml.bz2": b"BZh"}
_COMPRESSION = {"xml.gz": "gzip", "xml.bz2": "bzip2"}


def _compressed_scan(path: Path, fmt: str) -> tuple[bytes, bytes, int]:
    """The first :data:`PROLOG_LIMIT` bytes, the last bytes and the size of what a gzip or bzip2 file
    holds, decompressed as a stream (members one after the other, as ``gzip`` and ``pbzip2`` write
    them)."""
    compressed = os.path.getsize(path)
    head, tail, size = bytearray(), b"", 0
    decompressor, fed = _decompressor(fmt), False
    with open(path, "rb") as handle:
        while chunk := handle.read(_CHUNK):
            pending: bytes | None = chunk
            while pending is not None:
                try:
                    out = decompressor.decompress(pending, _CHUNK)
                except (zlib.error, OSError, EOFError) as exc:
                    raise CityMapError(
                        f"{path} is a damaged {_COMPRESSION[fmt]} file ({exc}); fetch it again"
                    ) from None
                fed = True
                size += len(out)
                if len(head) < PROLOG_LIMIT:
                    head += out[: PROLOG_LIMIT - len(head)]
                tail = (tail + out)[-_TAIL:]
                if (error := _bomb(path, size, compressed)) is not None:
                    raise error
                if decompressor.eof:
                    rest = decompressor.unused_data
                    decompressor, fed = _decompressor(fmt), False
                    # the next member, or trailing bytes after the last one (ignored, as gzip does)
                    pending = rest if rest.startswith(_MAGIC[fmt]) else None
                else:
                    pending = _held_back(decompressor)
    if fed:
        raise CityMapError(
            f"{path} ends inside its {_COMPRESSION[fmt]} stream: the file is truncated; fetch it again"
        )
    return bytes(head), tail, size


def _held_back(decompressor) -> bytes | None:
    """What to feed a decompressor that stopped at its output limit, or None when it wants the next
    chunk: zlib hands the unread input back, bz2 keeps it and is called again with nothing."""
    if isinstance(decompressor, bz2.BZ2Decompressor):
        return None if decompressor.needs_input else b""
    return decompressor.unconsumed_tail or None


def _truncated_pbf(path: Path) -> CityMapError:
    return CityMapError(f"{path} ends inside a PBF block: the file is truncated; fetch it again")


def _varint(stream: IO[bytes], path: Path) -> int:
    value, shift = 0, 0
    while True:
        byte = stream.read(1)
        if not byte:
            raise _truncated_pbf(path)
        value |= (byte[0] & 0x7F) << shift
        if byte[0] < 0x80:
            return value
        shift += 7
        if shift > 63:
            raise CityMapError(f"{path} is not a valid PBF file (a malformed number)")


def _fields(stream: IO[bytes], end: int, path: Path) -> dict[int, int]:
    """The fields of a protobuf message ending at offset ``end``: varints as their value, other
    fields as their length (their bytes are skipped, never read)."""
    fields: dict[int, int] = {}
    while stream.tell() < end:
        key = _varint(stream, path)
        field, wire = key >> 3, key & 7
        if wire == 0:
            fields[field] = _varint(stream, path)
        elif wire == 2:
            fields[field] = _varint(stream, path)
            stream.seek(fields[field], os.SEEK_CUR)
        else:
            raise CityMapError(f"{path} is not a valid PBF file (a field of wire type {wire})")
    return fields


def _pbf_block(handle: IO[bytes], size: int, path: Path) -> int:
    """Walk one PBF block (header length, ``BlobHeader``, ``Blob``): its decompressed size."""
    if size - handle.tell() < 4:
        raise _truncated_pbf(path)
    length = int.from_bytes(handle.read(4), "big")
    if not 0 < length <= _MAX_BLOB_HEADER:
        raise CityMapError(f"{path} is not a valid PBF file (a block header of {length} bytes)")
    header = handle.read(length)
    if len(header) < length:
        raise _truncated_pbf(path)
    fields = _fields(io.BytesIO(header), length, path)  # 1: type, 3: datasize
    datasize = fields.get(3, 0)
    if 1 not in fields or not 0 < datasize <= _MAX_BLOB:
        raise CityMapError(f"{path} is not a valid PBF file (a block of {datasize} bytes)")
    start = handle.tell()
    if start + datasize > size:
        raise _truncated_pbf(path)
    blob = _fields(handle, start + datasize, path)  # 1: raw data, 2: raw_size of compressed data
    handle.seek(start + datasize)
    raw = blob.get(2, blob.get(1, 0))
    if raw > _MAX_BLOB:
        raise CityMapError(f"{path} is not a valid PBF file (a block of {raw} bytes decompressed)")
    return raw


def _pbf_scan(path: Path) -> int:
    """The decompressed size of a PBF file's blocks, from their headers (their data is skipped, not
    read); a block reaching past the end of the file means the file is truncated."""
    size = os.path.getsize(path)
    total = 0
    with open(path, "rb") as handle:
        while handle.tell() < size:
            total += _pbf_block(handle, size, path)
            if (error := _bomb(path, total, size)) is not None:
                raise error
    return total


@dataclass(frozen=True)
class OsmFile:
    """An OSM file that passed :func:`check_osm_file`.

    Attributes
    ----------
    path : Path
        The file.
    format : str
        ``"xml"``, ``"xml.gz"``, ``"xml.bz2"`` or ``"pbf"``.
    data_bytes : int
        What it holds decompressed: the XML text, or the sum of the PBF blocks.
    """

    path: Path
    format: str
    data_bytes: int


def _raw_head(path: Path) -> tuple[str, bytes]:
    """The format of a file, from its first bytes (whatever its name), and those raw bytes."""
    problem = regular_file_problem(path, max_bytes=MAX_OSM_BYTES, what="OSM file")
    if problem:
        raise CityMapError(problem)
    with open(path, "rb") as handle:
        head = handle.read(PROLOG_LIMIT)
    kind = _content_kind(head)
    if kind == "empty":
        raise CityMapError(f"{path} is empty: give {ACCEPTED}")
    if kind not in _FORMATS:
        raise CityMapError(
            f"{path} is not an OSM file (it is neither XML, gzip, bzip2 nor PBF data): give {ACCEPTED}"
        )
    return _FORMATS[kind], head


def _holds_xml(head: bytes, path: Path, fmt: str) -> None:
    """Refuse a compressed file that does not hold XML."""
    if _content_kind(head) != "xml":
        raise CityMapError(f"{path} is {_COMPRESSION[fmt]} but does not hold OSM XML: give {ACCEPTED}")


def check_osm_file(path: str | os.PathLike[str]) -> OsmFile:
    """Check an OSM file before any parser opens it: what it is and how much data it holds.

    Parameters
    ----------
    path : path
        An OSM file (XML, gzipped or bzip2-compressed XML, or PBF; its name does not matter).

    Returns
    -------
    OsmFile
        Its format and decompressed size.

    Raises
    ------
    CityMapError
        If the file is missing, not a regular file, too large, empty, not OSM data, truncated, a
        decompression bomb, or XML with a DOCTYPE or a root other than ``<osm>``.
    """
    path = Path(path)
    fmt, head = _raw_head(path)
    if fmt == "pbf":
        return OsmFile(path, fmt, _pbf_scan(path))
    if fmt == "xml":
        size = os.path.getsize(path)
        with open(path, "rb") as handle:
            handle.seek(max(0, size - _TAIL))
            tail = handle.read()
    else:
        head, tail, size = _compressed_scan(path, fmt)
        _holds_xml(head, path, fmt)
    _check_prolog(head, path, complete=len(head) < PROLOG_LIMIT)
    _check_xml_tail(tail, path)
    return OsmFile(path, fmt, size)


def peek_osm_file(path: str | os.PathLike[str]) -> tuple[str, bytes]:
    """What :func:`check_osm_file` checks of a file's beginning, reading only its first bytes.

    The name, the content's kind, and for XML the prolog (no DOCTYPE, an ``<osm>`` root), from at
    most :data:`PROLOG_LIMIT` bytes (decompressed from the start of a gzip file): cheap enough for
    validating recipes. Sizes, truncation and bombs are checked when the file is read.

    Returns
    -------
    format : str
        ``"xml"``, ``"xml.gz"``, ``"xml.bz2"`` or ``"pbf"``.
    head : bytes
        The first bytes of the (decompressed) XML; empty for PBF.

    Raises
    ------
    CityMapError
        If the name, the content or the XML prolog is wrong.
    """
    path = Path(path)
    fmt, head = _raw_head(path)
    if fmt == "pbf":
        return fmt, b""
    if fmt in _COMPRESSION:
        with open(path, "rb") as handle:
            try:
                head = _decompressor(fmt).decompress(handle.read(_CHUNK), PROLOG_LIMIT)
            except (zlib.error, OSError, EOFError) as exc:
                raise CityMapError(f"{path} is not readable {_COMPRESSION[fmt]}: {exc}") from None
        _holds_xml(head, path, fmt)
    _check_prolog(head, path, complete=len(head) < PROLOG_LIMIT)
    return fmt, head


_BOUNDS = re.compile(rb"<bounds\b([^<>]*)>")
_ATTRIBUTE = re.compile(rb"""\b(minlat|minlon|maxlat|maxlon)\s*=\s*["']([^"']{1,40})["']""")


def head_bounds(head: bytes) -> LonLatBox | None:
    """The ``<bounds>`` an OSM XML file declares within its first bytes, or None.

    Reading them from the head keeps validation bounded: a parser asked for the header of an XML file
    reads on until its first object.
    """
    match = _BOUNDS.search(head)
    if match is None:
        return None
    values: dict[str, float] = {}
    for key, value in _ATTRIBUTE.findall(match.group(1)):
        try:
            values[key.decode()] = float(value)
        except ValueError:
            return None
    if set(values) != {"minlat", "minlon", "maxlat", "maxlon"} or not all(
        map(math.isfinite, values.values())
    ):
        return None
    box = (values["minlon"], values["minlat"], values["maxlon"], values["maxlat"])
    if not (-180 <= box[0] <= box[2] <= 180 and -90 <= box[1] <= box[3] <= 90):
        return None
    return box


def osmium_failure(path: Path, fmt: str, exc: Exception) -> CityMapError:
    """The :class:`CityMapError` for an error osmium raised reading ``path`` (of format ``fmt``)."""
    message = str(exc)
    lowered = message.lower()
    ends = ("eof", "truncated", "no element found", "unclosed token", "gzip error", "read close failed")
    what = {"pbf": "OSM PBF", "xml": "OSM XML", "xml.gz": "gzipped OSM XML", "xml.bz2": "bzip2 OSM XML"}[fmt]
    if any(word in lowered for word in ends):
        return CityMapError(
            f"{path} ends early or is damaged ({message}): the file is truncated or corrupt; "
            "fetch or export it again"
        )
    return CityMapError(f"{path} cannot be read as {what} ({message}): fix the file or export it again")


def osmium_file(path: str | os.PathLike[str], fmt: str) -> osmium.io.File:
    """``path`` for osmium, with its format (one of :class:`OsmFile`'s) given, never guessed from the name."""
    return osmium.io.File(str(path), OSMIUM_FORMATS[fmt])


def file_bounds(path: str | os.PathLike[str], fmt: str) -> LonLatBox | None:
    """The data bounds the file's header declares (``<bounds>``, the PBF header bbox), or None."""
    try:
        reader = osmium.io.Reader(osmium_file(path, fmt), osmium.osm.NOTHING)
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


EXTENT_PERCENTILES = (5.0, 95.0)
"""Percentiles of the nodes' longitudes and latitudes that bound a file's data when it declares no bounds."""
_MOST_SPREAD_NODES = 2_000_000
"""Nodes kept to find where the data is; beyond, every other one is dropped (in file order), repeatedly."""


@dataclass(frozen=True)
class NodeSpread:
    """Where a file's nodes lie: ``box`` spans the :data:`EXTENT_PERCENTILES` of their longitudes and
    latitudes (a few far nodes of a relation do not stretch it); ``centre`` (lat, lon) is the node
    nearest their median, so a window around it holds data even when the data is a thin corridor."""

    box: LonLatBox
    centre: tuple[float, float]


def node_spread(path: str | os.PathLike[str], fmt: str) -> NodeSpread | None:
    """Where the data of a file without declared bounds (an Overpass export) lies; None if no node
    has a location."""
    lons: list[float] = []
    lats: list[float] = []
    step, seen = 1, 0
    try:
        for node in osmium.FileProcessor(osmium_file(path, fmt), osmium.osm.NODE):
            location = node.location
            if not location.valid():
                continue
            seen += 1
            if seen % step:
                continue
            lons.append(location.lon)
            lats.append(location.lat)
            if len(lons) >= _MOST_SPREAD_NODES:
                lons, lats, step = lons[::2], lats[::2], step * 2
    except OSMIUM_ERRORS as exc:
        raise osmium_failure(Path(path), fmt, exc) from None
    if not lons:
        return None
    lon_array, lat_array = np.asarray(lons), np.asarray(lats)
    low, high = EXTENT_PERCENTILES
    west, east = (float(v) for v in np.percentile(lon_array, [low, high]))
    south, north = (float(v) for v in np.percentile(lat_array, [low, high]))
    median_lon, median_lat = float(np.median(lon_array)), float(np.median(lat_array))
    shrink = math.cos(math.radians(median_lat))  # degrees of longitude are shorter
    nearest = int(np.argmin(((lon_array - median_lon) * shrink) ** 2 + (lat_array - median_lat) ** 2))
    return NodeSpread(
        box=(west, south, east, north), centre=(lat_array[nearest].item(), lon_array[nearest].item())
    )
