"""Reduced-order models: ``lip`` (ω, the closed-form LIP flow and the DCM: the one copy), ``lip3d``
(paper A's step-to-step 3D-LIP with heading) and ``alip`` (paper B's ALIP / DCM step-to-step map)."""

__all__ = ["lip", "lip3d", "alip"]
