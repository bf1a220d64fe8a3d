"""Where a user's simulator departs from the seed's algorithm: the moments its step is called
from, the catalogue of known mistakes, the law sentences, and the diagnosis that holds them."""
from .diagnose import diagnose, diagnosis, diagnosis_markdown, render_markdown

__all__ = ["diagnose", "diagnosis", "diagnosis_markdown", "render_markdown"]
