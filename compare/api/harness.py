"""What the pytest fixture `contact_harness` gives a test: the API, with the plugin's
--contact-sim, --contact-scenes and --contact-law as its defaults."""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Harness:
    """judge and identify, defaulting to the command line's choices (None: not given there)."""

    sim: str | None = None                  # --contact-sim
    scenes: tuple[str, ...] | None = None   # --contact-scenes (None: every built-in)
    law: str | None = None                  # --contact-law
    whole: bool = False                     # --contact-whole

    def judge(self, sim=None, scenes=None, *, law=None, whole=None, out=None, **options):
        """compare.judge, with this harness's sim, scenes, law and whole where not given."""
        from .judge import judge
        return judge(self._sim(sim), self.scenes if scenes is None else scenes, law=law or self.law,
                     whole=self.whole if whole is None else whole, out=out, **options)

    def identify(self, sim=None, scenes=None, *, whole=None):
        """compare.identify, with this harness's sim and scenes where not given."""
        from .identify import identify_scenes
        return identify_scenes(self._sim(sim), self.scenes if scenes is None else scenes,
                               whole=self.whole if whole is None else whole)

    def _sim(self, sim):
        if sim is None and self.sim is None:
            from scene_types import BadInput
            raise BadInput("contact_harness: expected a simulator (judge(sim) or pytest --contact-sim MODULE:FUNCTION)")
        return self.sim if sim is None else sim
