"""The base of every library settings model: one declaration per setting.

A setting (its type, bounds, default and docstring) is declared once, on a :class:`Settings` model
of the library module that uses it. The Python API passes such a model; a pipeline stage's
parameter model derives from it (``class PopulateParams(Params, PopulateSettings)``), so the recipe
schema, the stage, the library and the API read the same declaration, and a stage hands the
library :meth:`Settings.of` its parameters. Models compose by inheritance where a recipe section
covers several (a city's geometry settings are its ground settings and more), so recipe keys stay
flat. ``tests/test_settings.py`` walks the stage registry and fails on a setting declared twice.
"""

from __future__ import annotations

from typing import Any, TypeVar

from pydantic import BaseModel, ConfigDict

__all__ = ["Settings"]

S = TypeVar("S", bound="Settings")


class Settings(BaseModel):
    """Frozen, strict-keyed, bounded settings of a library call.

    Unknown keys are errors, instances are immutable, non-finite floats are refused and defaults
    are validated (as a stage's parameters are). A field's docstring (the string literal under it)
    is its description.
    """

    model_config = ConfigDict(
        extra="forbid",
        frozen=True,
        validate_default=True,
        allow_inf_nan=False,
        use_attribute_docstrings=True,
    )

    @classmethod
    def of(cls: type[S], values: BaseModel, **changes: Any) -> S:
        """This model with the values of its fields taken from ``values``.

        Parameters
        ----------
        values : BaseModel
            A model that has every field of this one: typically a stage's parameters, which derive
            from this model and add stage-only fields (which are left out).
        **changes
            Fields to set otherwise.

        Returns
        -------
        Settings
            An instance of exactly this class (not of the stage's subclass), validated.
        """
        data = {name: getattr(values, name) for name in cls.model_fields}
        return cls.model_validate({**data, **changes})
