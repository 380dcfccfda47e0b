"""Assembly core and graph → model builder of the general torsional model (issue 11)."""

from geardyn.models.core.graph import build_model, model_from_config
from geardyn.models.core.model import Body, CoreModel, MeshElement, Spring

__all__ = ["Body", "CoreModel", "MeshElement", "Spring", "build_model", "model_from_config"]
