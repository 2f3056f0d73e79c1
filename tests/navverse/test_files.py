"""Atomic writes: the target holds the old content or the whole new one, and nothing is left behind."""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Literal

import numpy as np
import pytest

from navverse.files import atomic_dir, atomic_path, atomic_write, cached_file_sha256, file_sha256


def test_a_file_appears_only_when_written_whole(tmp_path: Path) -> None:
    target = tmp_path / "data.bin"
    target.write_bytes(b"old")
    with atomic_write(target) as handle:
        handle.write(b"new, first half; ")
        handle.flush()
        assert target.read_bytes() == b"old"
        (tmp,) = (p for p in tmp_path.iterdir() if p != target)
        assert tmp.parent == tmp_path and tmp.name.startswith(".data.bin.") and tmp.name.endswith(".tmp")
        assert list(tmp_path.glob("*.bin")) == [target]  # a reader's pattern sees the target only
        handle.write(b"second half")
    assert target.read_bytes() == b"new, first half; second half"
    assert list(tmp_path.iterdir()) == [target]


def test_text_is_written_in_the_encoding_given(tmp_path: Path) -> None:
    target = tmp_path / "page.html"
    with atomic_write(target, mode="w") as handle:
        handle.write("Café ≤ 1 m\n")
    assert target.read_bytes() == "Café ≤ 1 m\n".encode()
    with atomic_write(target, mode="w", encoding="latin-1") as handle:
        handle.write("Café\n")
    assert target.read_bytes() == b"Caf\xe9\n"


@pytest.mark.parametrize("error", [RuntimeError, KeyboardInterrupt])
@pytest.mark.parametrize("mode", ["wb", "w"])
def test_an_error_in_the_block_leaves_the_target_and_no_temporary_file(
    tmp_path: Path, error: type[BaseException], mode: Literal["wb", "w"]
) -> None:
    target = tmp_path / "data.json"
    target.write_text('{"old": true}')
    with pytest.raises(error), atomic_write(target, mode=mode) as handle:
        handle.write(b"{" if mode == "wb" else "{")
        raise error
    assert target.read_text() == '{"old": true}'
    assert list(tmp_path.iterdir()) == [target]


def test_a_missing_directory_is_an_error_that_leaves_nothing(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError), atomic_write(tmp_path / "absent" / "x.bin") as handle:
        handle.write(b"x")
    assert list(tmp_path.iterdir()) == []


def test_concurrent_writers_of_one_file_each_write_whole(tmp_path: Path) -> None:
    target = tmp_path / "shared.bin"
    contents = [bytes([k]) * 100_000 for k in range(8)]
    halfway = threading.Barrier(len(contents))  # every writer is in the middle of its file at once

    def write(content: bytes) -> None:
        with atomic_write(target) as handle:
            handle.write(content[:50_000])
            handle.flush()
            halfway.wait(timeout=10)
            handle.write(content[50_000:])

    threads = [threading.Thread(target=write, args=(c,)) for c in contents]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert target.read_bytes() in contents
    assert list(tmp_path.iterdir()) == [target]


def test_a_path_for_a_writer_that_names_the_file_itself(tmp_path: Path) -> None:
    target = tmp_path / "hulls.npz"
    arrays = {"hull_0": np.arange(12.0).reshape(4, 3), "hull_1": np.ones((5, 3))}
    with atomic_path(target) as tmp:
        assert tmp.parent == tmp_path and tmp.suffix == ".npz" and not tmp.exists()
        np.savez(tmp, **arrays)  # savez appends ".npz" to a name without it: the suffix is kept
        assert not target.exists()
    with np.load(target) as data:
        assert sorted(data.files) == sorted(arrays)
        assert all(np.array_equal(data[k], v) for k, v in arrays.items())
    assert list(tmp_path.iterdir()) == [target]


def test_a_path_whose_writer_fails_or_writes_nothing_leaves_the_target(tmp_path: Path) -> None:
    target = tmp_path / "fields.npz"
    target.write_bytes(b"old")
    with pytest.raises(ValueError), atomic_path(target) as tmp:
        np.savez(tmp, a=np.zeros(3))
        raise ValueError("the writer failed after writing")
    with pytest.raises(FileNotFoundError), atomic_path(target):
        pass
    assert target.read_bytes() == b"old"
    assert list(tmp_path.iterdir()) == [target]


def test_a_directory_appears_whole_or_not_at_all(tmp_path: Path) -> None:
    target = tmp_path / "v1.0"
    with atomic_dir(target) as staging:
        (staging / "train").mkdir()
        (staging / "train" / "objnav.json.gz").write_bytes(b"episodes")
        assert not target.exists() and not list(tmp_path.glob("v*"))
    assert (target / "train" / "objnav.json.gz").read_bytes() == b"episodes"
    assert list(tmp_path.iterdir()) == [target]

    failed = tmp_path / "v2.0"
    with pytest.raises(KeyboardInterrupt), atomic_dir(failed) as staging:
        (staging / "manifest.json").write_text("{}")
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == [target]


def test_a_cached_hash_follows_the_file_when_it_is_rewritten(tmp_path: Path) -> None:
    path = tmp_path / "scene.usdc"
    path.write_bytes(b"first")
    first = cached_file_sha256(path)
    assert first == file_sha256(path) == cached_file_sha256(tmp_path / "." / "scene.usdc")
    with atomic_write(path) as handle:  # replaced: another inode
        handle.write(b"second, longer")
    assert cached_file_sha256(path) == file_sha256(path) != first
