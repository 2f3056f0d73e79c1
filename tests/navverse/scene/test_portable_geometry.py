"""Generated geometry is the same bytes on other processors.

Another x86-64 machine differs from this one in numpy's AVX-512 functions (``exp``, ``log``,
``arctan2``, ``power``...), in OpenBLAS's kernels behind ``@`` and ``dot``, and in glibc's use of fused
multiply-adds in ``sin``/``cos``: each changes the last bit of some results. The objects most affected
(before vertices were snapped and placements rounded, each of these differed) are built here in a
process as this machine runs it and in one that runs as a processor without AVX-512, AVX2 and FMA
would, and must hash the same.
"""

from __future__ import annotations

import os
import platform
import subprocess
import sys

import numpy as np
import pytest

from navverse.scene.annotations import ObjectAnnotation
from navverse.scene.geometry import VERTEX_GRID, apply_linear, snap_to_grid, yaw_matrix

# Each differed between the two processes before: handbag and suitcase with numpy's AVX-512 functions,
# potted_plant, bush and pickup_truck with OpenBLAS's kernel, floor_lamp and vase with glibc's FMA.
SENSITIVE = ["handbag", "suitcase", "potted_plant", "bush", "pickup_truck", "floor_lamp", "vase"]
HASH_OBJECTS = """
import hashlib, sys
import numpy as np
from navverse.assets.library import make_object
digest = hashlib.sha256()
for category in sys.argv[1:]:
    for seed in range(4):
        mesh, _ = make_object(category, np.random.default_rng(seed))
        digest.update(mesh.vertices.tobytes())
        digest.update(mesh.faces.tobytes())
print(digest.hexdigest())
"""


def _other_processor() -> dict[str, str]:
    """Environment under which numpy, OpenBLAS and glibc take the code paths of an older x86-64."""
    try:  # numpy 2
        from numpy._core._multiarray_umath import __cpu_features__ as features
    except ImportError:  # numpy 1.26
        from numpy.core._multiarray_umath import __cpu_features__ as features

    # numpy 2 names its AVX-512 dispatch targets X86_V4, AVX512_ICL, AVX512_SPR; numpy 1.26 AVX512F, ...
    avx512 = [name for name, found in features.items() if found and ("AVX512" in name or name == "X86_V4")]
    env = {
        **os.environ,
        "OPENBLAS_CORETYPE": "Nehalem",
        "GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F",
    }
    if avx512:
        env["NPY_DISABLE_CPU_FEATURES"] = " ".join(avx512)
    return env


def _hash_objects(env: dict[str, str]) -> str:
    result = subprocess.run(
        [sys.executable, "-c", HASH_OBJECTS, *SENSITIVE], env=env, capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr
    return result.stdout.strip()


@pytest.mark.skipif(
    platform.system() != "Linux" or platform.machine() != "x86_64",
    reason="the emulated processors are x86-64",
)
@pytest.mark.slow(seconds=20)
def test_objects_are_the_same_bytes_on_another_processor() -> None:
    assert _hash_objects(dict(os.environ)) == _hash_objects(_other_processor())


def test_snapping_removes_last_bit_differences() -> None:
    values = np.array([0.1 + 0.2, 1234.5678, -7.25, 1e-9])
    nudged = np.nextafter(values, np.inf)
    assert np.array_equal(snap_to_grid(values), snap_to_grid(nudged))
    assert np.all(np.abs(snap_to_grid(values) - values) <= 0.5 * VERTEX_GRID)
    assert snap_to_grid(-7.25) == -7.25  # a multiple of the grid stays as it is
    assert not np.signbit(snap_to_grid(np.array([-1e-12, -0.0]))).any()  # no -0.0 from noise about 0


def test_apply_linear_is_the_matrix_product() -> None:
    points = np.random.default_rng(0).normal(size=(50, 3)) * 100.0
    matrix = yaw_matrix(0.7)
    assert np.allclose(apply_linear(points, matrix), points @ matrix.T, rtol=0, atol=1e-12)


def test_annotation_positions_are_rounded_to_the_nanometre() -> None:
    center = (0.1 + 0.2, float(np.nextafter(-5.927290870821208, 0.0)), 0.7)
    other = (0.3, -5.927290870821208, 0.7)
    made = [
        ObjectAnnotation(
            id=1, category="bench", prim_path="/World/Objects/a", center=c, size=(1.0, 0.5, 0.8), yaw=y
        )
        for c, y in ((center, 0.1 + 0.2), (other, 0.3))
    ]
    assert made[0].center == made[1].center == (0.3, -5.927290871, 0.7)
    assert made[0].yaw == made[1].yaw == 0.3
