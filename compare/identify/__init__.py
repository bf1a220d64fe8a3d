"""Which contact law a user's simulator implements: each effect's family and parameters, or none."""
from .contact import NotIdentified, identified_contact, identified_scene
from .from_step import identify_step
from .whole_run import identify_run

__all__ = ["NotIdentified", "identified_contact", "identified_scene", "identify_run", "identify_step"]
