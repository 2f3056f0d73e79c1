"""A dataset version that is not as it was packaged is refused, by the API and by every command that uses it.

Each case tampers with a copy of a tiny dataset built by :func:`tests.navverse.test_dataset.build`; the
reader must name the file and say what to do, the commands must exit 1 without a traceback.
"""

from __future__ import annotations

import gzip
import hashlib
import json
import os
import shutil
import zlib
from collections.abc import Callable
from pathlib import Path

import pytest

from navverse import cli
from navverse.dataset import MAX_FILE_BYTES, MAX_MANIFEST_BYTES, Dataset, DatasetError, read_json_gz
from tests.navverse.test_dataset import build

REMEDY = "re-download it, or rebuild it with `navverse build <dataset>`"


def _edit_manifest(root: Path, edit: Callable[[dict], None]) -> None:
    manifest = json.loads((root / "manifest.json").read_text())
    edit(manifest)
    (root / "manifest.json").write_text(json.dumps(manifest, indent=2))


def _relist(root: Path, name: str) -> None:
    """Give ``name`` its current checksum in the manifest (a tamperer who also edits the manifest)."""
    digest = hashlib.sha256((root / name).read_bytes()).hexdigest()
    _edit_manifest(root, lambda m: m["files"].__setitem__(name, digest))


def _move_goals(root: Path) -> None:
    path = root / "eval" / "objnav.json.gz"
    data = json.loads(gzip.decompress(path.read_bytes()))
    for episode in data["episodes"]:
        episode["goals"][0]["position"][0] += 3.0
    path.write_bytes(gzip.compress(json.dumps(data).encode(), mtime=0))


def _symlink(root: Path) -> None:
    path = root / "eval" / "objnav.json.gz"
    outside = root.parent / "outside.json.gz"
    shutil.copy(path, outside)
    path.unlink()
    os.symlink(outside, path)


def _bump_count(manifest: dict) -> None:
    manifest["counts"]["eval"]["objnav"]["indoor"] += 1


def _entry(name: str) -> Callable[[dict], None]:
    return lambda manifest: manifest["files"].__setitem__(name, "0" * 64)


# case: (tamper with the copy, text the error must hold)
CASES: dict[str, tuple[Callable[[Path], None], str]] = {
    "modified episode file": (
        _move_goals,
        "files differ from the manifest's checksums: eval/objnav.json.gz",
    ),
    "deleted file": (
        lambda root: (root / "eval" / "objnav.json.gz").unlink(),
        "files listed in manifest.json are missing: eval/objnav.json.gz",
    ),
    "deleted file and its entry": (
        lambda root: (
            (root / "eval" / "objnav.json.gz").unlink(),
            _edit_manifest(root, lambda m: m["files"].pop("eval/objnav.json.gz")),
        ),
        "counts eval/objnav/indoor is 2 in manifest.json but the episode files hold 0",
    ),
    "extra file": (
        lambda root: shutil.copy(root / "eval" / "objnav.json.gz", root / "eval" / "vln.json.gz"),
        "files are not listed in manifest.json (added or renamed): eval/vln.json.gz",
    ),
    "extra file, listed": (
        lambda root: (
            shutil.copy(root / "eval" / "objnav.json.gz", root / "eval" / "vln.json.gz"),
            _relist(root, "eval/vln.json.gz"),
        ),
        "eval/vln.json.gz: flat-s1-objnav-0000 is an episode of task objnav",
    ),
    "empty files": (
        lambda root: _edit_manifest(root, lambda m: m.__setitem__("files", {})),
        "files are not listed in manifest.json (added or renamed): eval/objnav.json.gz",
    ),
    "parent entry": (
        lambda root: _edit_manifest(root, _entry("../../etc/hostname")),
        "files entry '../../etc/hostname' leaves the version directory",
    ),
    "absolute entry": (
        lambda root: _edit_manifest(root, _entry("/etc/hostname")),
        "files entry '/etc/hostname' is an absolute path",
    ),
    "symlink entry": (
        _symlink,
        "files are symbolic links, not regular files: eval/objnav.json.gz",
    ),
    "fifo entry": (
        lambda root: (
            (root / "eval" / "objnav.json.gz").unlink(),
            os.mkfifo(root / "eval" / "objnav.json.gz"),
        ),
        "files are not regular files: eval/objnav.json.gz",
    ),
    "counts changed": (
        lambda root: _edit_manifest(root, _bump_count),
        "counts eval/objnav/indoor is 3 in manifest.json but the episode files hold 2",
    ),
    "duplicate key": (
        lambda root: (root / "manifest.json").write_text(
            (root / "manifest.json")
            .read_text()
            .replace('"files": {', f'"files": {{"eval/objnav.json.gz": "{"0" * 64}",', 1)
        ),
        "the key 'eval/objnav.json.gz' appears twice",
    ),
    "huge manifest": (
        lambda root: _edit_manifest(root, lambda m: m.__setitem__("recipe", "x" * MAX_MANIFEST_BYTES)),
        "manifest.json is larger than 4 MiB",
    ),
}


@pytest.fixture(scope="module")
def bomb(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A small gzip file that decompresses to just over :data:`MAX_FILE_BYTES` of zeros."""
    path = tmp_path_factory.mktemp("bomb") / "bomb.json.gz"
    compressor = zlib.compressobj(1, zlib.DEFLATED, 31)
    zeros = bytes(1 << 20)
    with path.open("wb") as handle:
        for _ in range(MAX_FILE_BYTES // len(zeros) + 1):
            handle.write(compressor.compress(zeros))
        handle.write(compressor.flush())
    assert path.stat().st_size < 8 << 20
    return path


@pytest.fixture(scope="module")
def pristine(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build(tmp_path_factory.mktemp("pristine") / "tiny" / "v1.0")


def _tampered(pristine: Path, tmp_path: Path, case: str, bomb: Path) -> tuple[Path, str]:
    root = tmp_path / "tiny" / "v1.0"
    shutil.copytree(pristine, root)
    if case == "gzip bomb":
        shutil.copy(bomb, root / "eval" / "objnav.json.gz")
        _relist(root, "eval/objnav.json.gz")  # even with a matching checksum
        return root, "files are larger than 512 MiB (compressed or decompressed): eval/objnav.json.gz"
    tamper, message = CASES[case]
    tamper(root)
    return root, message


ALL_CASES = [*CASES, "gzip bomb"]


def _refused(call: Callable[[], object]) -> str:
    with pytest.raises(DatasetError) as caught:
        call()
    return " ".join(str(caught.value).split())


def test_a_sound_dataset_verifies(pristine: Path):
    dataset = Dataset(pristine)
    dataset.verify()
    assert dataset.verify_checksums() == []
    digest = hashlib.sha256((pristine / "manifest.json").read_bytes()).hexdigest()
    assert dataset.manifest_sha256 == digest


@pytest.mark.parametrize("case", ALL_CASES)
def test_the_api_refuses_a_tampered_dataset_naming_the_file(
    pristine: Path, tmp_path: Path, case: str, bomb: Path
):
    root, message = _tampered(pristine, tmp_path, case, bomb)
    text = _refused(lambda: Dataset(root).verify())
    assert message in text
    assert REMEDY in text


@pytest.mark.parametrize("case", ["modified episode file", "deleted file", "symlink entry", "gzip bomb"])
def test_the_reader_checks_a_file_before_it_reads_it_even_without_verify(
    pristine: Path, tmp_path: Path, case: str, bomb: Path
):
    root, message = _tampered(pristine, tmp_path, case, bomb)
    dataset = Dataset(root)
    assert message in _refused(lambda: list(dataset.episodes(split="eval")))
    assert [e.episode_id for e in dataset.episodes(split="train")]  # the sound file still reads


def test_read_json_gz_stops_at_its_limit(bomb: Path):
    with pytest.raises(DatasetError, match="decompresses to more than 1 MiB"):
        read_json_gz(bomb, max_bytes=1 << 20)


@pytest.mark.parametrize("case", ALL_CASES)
def test_every_command_refuses_a_tampered_dataset_cleanly(
    pristine: Path, tmp_path: Path, case: str, bomb: Path, capsys: pytest.CaptureFixture[str]
):
    root, message = _tampered(pristine, tmp_path, case, bomb)
    out = tmp_path / "out"
    commands = [
        ["validate", "dataset", str(root)],
        ["eval", "--dataset", str(root), "--submission", str(tmp_path / "none.jsonl"), "--out", str(out)],
        ["run-agent", "--dataset", str(root), "--agent", "oracle", "--out", str(tmp_path / "run.jsonl")],
        ["show", "episode", str(root), "flat-s1-objnav-0000", "-o", str(tmp_path / "ep.png")],
    ]
    for argv in commands:
        assert cli.main(argv) == 1, argv
        captured = capsys.readouterr()
        error = " ".join(captured.err.split())
        assert message in error and "Traceback" not in captured.err + captured.out, (argv, error)
    assert [p.name for p in tmp_path.iterdir()] == ["tiny"]  # nothing written
