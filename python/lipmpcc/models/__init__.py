"""Reduced-order models: ``lip3d`` (paper A's step-to-step 3D-LIP with heading) and
``alip`` (paper B's ALIP / DCM step-to-step map)."""
