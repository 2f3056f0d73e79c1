"""The build engine: stages, recipes, a content-addressed artifact store, executors and a runner.

Generic by rule: it knows stages, artifacts, recipes and caching, and nothing of robotics.
"""

from pipeline.context import StageContext
from pipeline.errors import DagError, PipelineError, RecipeError, RecipeIssue, StoreError, TargetError
from pipeline.params import Params, SourceFile
from pipeline.stage import Input, StageSpec, discover, registered_stages, stage

__all__ = [
    "DagError",
    "Input",
    "Params",
    "PipelineError",
    "RecipeError",
    "RecipeIssue",
    "SourceFile",
    "StageContext",
    "StageSpec",
    "StoreError",
    "TargetError",
    "discover",
    "registered_stages",
    "stage",
]
