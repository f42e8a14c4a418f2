"""Fracture mechanics of cracked gear teeth: stress intensity, kink direction, life.

* :mod:`~gearsim.fracture.mesh`: gmsh meshes of bodies with polyline cracks, split faces;
* :mod:`~gearsim.fracture.sif`: K_I, K_II by the domain interaction integral;
* :mod:`~gearsim.fracture.closed_forms`: handbook K (Tada, Paris & Irwin; inclined crack);
* :mod:`~gearsim.fracture.plate`: FE check specimens with handbook K;
* :mod:`~gearsim.fracture.direction`: maximum tangential stress kink angle;
* :mod:`~gearsim.fracture.paris`: Paris law with threshold and toughness, life N(a);
* :mod:`~gearsim.fracture.tooth`: K at a tooth-root crack, MTS growth increments;
* :mod:`~gearsim.fracture.path`: a grown path with K along it (one load or a mesh
  cycle), and its Paris life;
* :mod:`~gearsim.fracture.compliance`: load-point compliance of the cracked sector.

Layer: above :mod:`gearsim.fem`, below :mod:`gearsim.system` (docs/fracture.md).
"""
