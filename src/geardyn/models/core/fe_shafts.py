"""Torsional FE shafts between the bodies of the mechanism model (``[[dynamics.shafts]]`` given
by geometry and material; SI units).

A shaft of length L, polar second moment I_p = π (D⁴ − d⁴) / 32, shear modulus G and density ρ
joining bodies a and b is a line of E two-node torsional elements of length L_e = L / E with
linear shape functions (Petyt 2010, *Introduction to Finite Element Vibration Analysis*, §3.2
"torsional vibration of shafts"; Friswell et al. 2010, *Dynamics of Rotating Machines*, ch. 5,
the torsional part of the shaft element):

    K_e = (G I_p / L_e) [[1, −1], [−1, 1]],     M_e = (ρ I_p L_e / 6) [[2, 1], [1, 2]]

(consistent mass: the kinetic energy of the linear interpolation, ½ ∫ ρ I_p θ̇² dx). Node 0 is
body a's rotation about its own axis (the row h_a of :class:`~geardyn.models.core.model.Body`),
node E body b's (0 when b is the frame: a fixed end), nodes 1 … E − 1 are new DOFs of the model,
``<shaft>.n<i>.theta`` (rad, absolute rotation about the shaft axis). With the map D (rows
h_a, e_n1, …, e_n(E−1), h_b) the shaft adds Dᵀ M_shaft D to the mass matrix, so its own inertia
ρ I_p L is distributed along it: the inertias of bodies a and b must not include the shaft
(the gear blanks never do; a given ``inertia_kgm2`` should not either).

Each element's stiffness is rank-one, k_e (θ_{i+1} − θ_i)² / 2 with k_e = E G I_p / L, so
the elements are stamped as rank-one springs of kind ``shaft`` named ``<shaft>.e<i>``
(the same K as a block; the rigid-body initial state and the modal strain energies then see
each element like any torsional shaft). A rigid rotation of the whole shaft with its ends
deflects no element, so the rigid-body modes stay the kinematic nullspace (seed 000 eq 5) with
the inner nodes turning with the shaft. ``damping_nms_per_rad`` c is stiffness-proportional,
C = (c / k) K (c_e = E c per element): for a massless shaft the same end-to-end damper as the
spring form.

Torsion only: in the lateral model (``lateral = true``) the shaft carries no bending or
lateral stiffness (a :class:`TorsionalOnlyWarning` says so).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np

from geardyn.config.dynamics import ShaftDynamics
from geardyn.models.core.assembly import Assembly
from geardyn.models.core.model import Spring

#: Kind of the FE shafts' element springs and mass blocks in the assembly.
SHAFT = "shaft"


class TorsionalOnlyWarning(UserWarning):
    """An FE shaft in the lateral model: torsion only, no bending (this version)."""


def node_name(shaft: str, i: int) -> str:
    """Name of inner node ``i`` (1 … E − 1) of an FE shaft."""
    return f"{shaft}.n{i}"


def inner_node_count(shafts: Sequence[ShaftDynamics]) -> int:
    """Number of new DOFs of the FE shafts among ``shafts`` (E − 1 each)."""
    return sum(sh.elements - 1 for sh in shafts if sh.is_fe)


def add_shaft_nodes(asm: Assembly, shafts: Sequence[ShaftDynamics]) -> list[int]:
    """Register the inner nodes ``<shaft>.n<i>.theta`` of every FE shaft (no point mass: the
    shaft's inertia is its consistent mass, :func:`stamp_fe_shaft`); returns their indices."""
    out: list[int] = []
    for sh in shafts:
        if sh.is_fe:
            for i in range(1, sh.elements):
                out += asm.add_dofs(node_name(sh.name, i), ["theta"])
    return out


def element_matrices(shaft: ShaftDynamics) -> tuple[np.ndarray, np.ndarray]:
    """(K_e, M_e) of one element (N·m/rad, kg·m²; module docstring, Petyt 2010 §3.2)."""
    le = float(shaft.length_m) / shaft.elements  # type: ignore[arg-type]
    ip = shaft.polar_moment_m4
    k = shaft.shear_modulus * ip / le
    m = shaft.density_kg_m3 * ip * le / 6
    return k * np.array([[1.0, -1.0], [-1.0, 1.0]]), m * np.array([[2.0, 1.0], [1.0, 2.0]])


def line_matrices(shaft: ShaftDynamics) -> tuple[np.ndarray, np.ndarray]:
    """(K, M) of the whole line over its E + 1 nodes (ends included)."""
    ke, me = element_matrices(shaft)
    n = shaft.elements + 1
    kk, mm = np.zeros((n, n)), np.zeros((n, n))
    for e in range(shaft.elements):
        kk[e:e + 2, e:e + 2] += ke
        mm[e:e + 2, e:e + 2] += me
    return kk, mm


def node_map(asm: Assembly, shaft: ShaftDynamics, end_a: np.ndarray,
             end_b: np.ndarray) -> np.ndarray:
    """D ((E + 1) × n): node rotations θ = D q (rows h_a, the inner nodes, h_b)."""
    rows = [np.asarray(end_a, float)]
    rows += [asm.row({f"{node_name(shaft.name, i)}.theta": 1.0})
             for i in range(1, shaft.elements)]
    rows.append(np.asarray(end_b, float))
    d = np.array(rows)
    if d.shape[1] != asm.n:
        raise ValueError(f"FE shaft '{shaft.name}': end rows of length {d.shape[1]} for "
                         f"{asm.n} DOFs (register the nodes before the elements)")
    return d


def stamp_fe_shaft(asm: Assembly, shaft: ShaftDynamics, end_a: np.ndarray,
                   end_b: np.ndarray, lateral: bool = False) -> list[Spring]:
    """Stamp an FE shaft between the rotations h_a·q and h_b·q (``end_b`` zero: the frame):
    its consistent mass Dᵀ M D (one block, kind ``inertia``) and one rank-one spring/damper per
    element (kind ``shaft``); returns the element springs."""
    if not shaft.is_fe:
        raise ValueError(f"shaft '{shaft.name}' is a torsional spring, not an FE shaft")
    if lateral:
        warnings.warn(f"dynamics.shafts '{shaft.name}': the FE shaft is torsional only (no "
                      "bending, no lateral stiffness) in the lateral model", TorsionalOnlyWarning,
                      stacklevel=3)
    d = node_map(asm, shaft, end_a, end_b)
    _kk, mm = line_matrices(shaft)
    asm.add_mapped(f"{shaft.name}.inertia", "inertia", d, M=mm)
    k_e = shaft.stiffness_nm_per_rad * shaft.elements
    c_e = shaft.damping_nms_per_rad * shaft.elements
    out = []
    for e in range(shaft.elements):
        sp = Spring(f"{shaft.name}.e{e + 1}", SHAFT, k_e, d[e + 1] - d[e], c_e)
        asm.add_rank_one(sp)
        out.append(sp)
    return out
