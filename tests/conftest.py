"""Suite-wide settings: the hypothesis profile that keeps property tests bounded and reproducible."""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

# Property tests run a bounded number of examples with a fixed derivation (no example database, no
# wall-clock deadline on a shared 2-core machine), so `make test` stays fast and gives the same result
# on every run. NAVVERSE_HYPOTHESIS=thorough runs many more examples when hunting for a bug.
settings.register_profile(
    "navverse",
    max_examples=60,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile("thorough", parent=settings.get_profile("navverse"), max_examples=2000)
settings.load_profile("thorough" if os.environ.get("NAVVERSE_HYPOTHESIS") == "thorough" else "navverse")
