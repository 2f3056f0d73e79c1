"""Exports of NavVerse datasets to other tools' layouts: :func:`export_habitat` (habitat-lab)."""

from navverse.export.habitat import HabitatExport, HabitatExportError, export_habitat

__all__ = ["HabitatExport", "HabitatExportError", "export_habitat"]
