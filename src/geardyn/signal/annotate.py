"""Annotation of spectra with the characteristic frequencies of a kinematics result.

:func:`spectral_markers` turns a :class:`~geardyn.kinematics.CharacteristicFrequencies` (one
operating speed) into a table of markers — shaft orders and harmonics, mesh orders and
harmonics with shaft-rate sidebands, bearing frequencies, tooth-fault (wheel) frequencies,
planet-pass frequencies and the dominant planet-pass components of seed 003 §4.1 — each in Hz
and in orders of the kinematics' order reference. :func:`annotate_axes` draws them on any
matplotlib spectrum plot (x axis in ``"order"`` or ``"hz"``).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from geardyn.errors import InputError

if TYPE_CHECKING:
    from geardyn.kinematics import CharacteristicFrequencies

KINDS = ("shaft", "mesh", "sideband", "bearing", "fault", "planet_pass", "planet_dominant")
_COLORS = {
    "shaft": "tab:blue",
    "mesh": "tab:red",
    "sideband": "tab:orange",
    "bearing": "tab:green",
    "fault": "tab:purple",
    "planet_pass": "tab:brown",
    "planet_dominant": "black",
}


def spectral_markers(
    freqs: CharacteristicFrequencies,
    shaft_harmonics: int = 3,
    mesh_harmonics: int = 3,
    sidebands: int = 2,
    bearing_harmonics: int = 1,
) -> pd.DataFrame:
    """Marker table with columns ``label, kind, hz, order`` (order = hz / reference_hz)."""
    ref = float(freqs.reference_hz)
    if ref <= 0:
        raise InputError("freqs: the order reference shaft does not turn (reference_hz = 0)")
    rows: list[dict[str, Any]] = []

    def add(label: str, kind: str, hz: float) -> None:
        if hz > 0 and np.isfinite(hz):
            rows.append({"label": label, "kind": kind, "hz": float(hz), "order": hz / ref})

    seen: set[float] = set()
    for _, r in freqs.links.iterrows():
        hz = float(r["hz"])
        key = round(hz, 9)
        if hz <= 0 or key in seen:
            continue
        seen.add(key)
        for h in range(1, shaft_harmonics + 1):
            add(f"{h}x {r['link']}", "shaft", h * hz)
    seen_mesh: set[float] = set()
    for _, r in freqs.meshes.iterrows():
        fm = float(r["mesh_hz"])
        key = round(fm, 9)
        if fm <= 0 or key in seen_mesh:
            continue
        seen_mesh.add(key)
        name = str(r["pair"])
        rel = sorted({round(float(r["rel_a_hz"]), 12), round(float(r["rel_b_hz"]), 12)})
        for h in range(1, mesh_harmonics + 1):
            add(f"{h}fm {name}", "mesh", h * fm)
            for fr in rel:
                for k in range(1, sidebands + 1):
                    add(f"{h}fm-{k}·{fr:.4g}Hz", "sideband", h * fm - k * fr)
                    add(f"{h}fm+{k}·{fr:.4g}Hz", "sideband", h * fm + k * fr)
    if len(freqs.bearings):
        for _, r in freqs.bearings.iterrows():
            name = str(r.get("bearing", r.get("name", "bearing")))
            for col in ("ftf_hz", "bpfo_hz", "bpfi_hz", "bsf_hz"):
                if col in r:
                    for h in range(1, bearing_harmonics + 1):
                        add(f"{h}{col[:-3].upper()} {name}", "bearing", h * float(r[col]))
    seen_fault: set[float] = set()
    for _, r in freqs.wheels.iterrows():
        hz = float(r["fault_hz"])
        if round(hz, 9) in seen_fault:
            continue
        seen_fault.add(round(hz, 9))
        add(f"fault {r['wheel']}", "fault", hz)
    for _, r in freqs.planet_pass.iterrows():
        add(f"planet pass {r['set']}", "planet_pass", float(r["planet_pass_hz"]))
        for lab, hz in planet_dominant_components(freqs, r, mesh_harmonics):
            add(lab, "planet_dominant", hz)
    return pd.DataFrame(rows, columns=["label", "kind", "hz", "order"])


def planet_dominant_components(
    freqs: CharacteristicFrequencies, row: pd.Series, harmonics: int = 3
) -> list[tuple[str, float]]:
    """Seed 003 §4.1 dominant-sideband rule for a sensor on the central member ``row.central``
    of a planetary set: near mesh harmonic h, the largest component is at ``N·round(h·Z/N)``
    orders of the carrier-relative rotation ``f_rel = f_pp/N`` (Z = teeth of the central gear).
    Only given for a non-rotating central member (a fixed ring carrying the accelerometer).
    """
    links = freqs.links.set_index("link")
    if row["central"] in links.index and float(links.loc[row["central"], "hz"]) != 0.0:
        return []
    n = int(row["n_planets"])
    f_rel = float(row["planet_pass_hz"]) / n
    m = freqs.meshes
    sel = m[(m["carrier"] == row["carrier"]) & (m["link_a"] == row["central"])]
    if sel.empty or f_rel <= 0:
        return []
    z = int(sel.iloc[0]["teeth_a"])
    out = []
    for h in range(1, harmonics + 1):
        k = n * round(h * z / n)
        out.append((f"dominant {h}fm {row['set']} ({k - h * z:+d} rel. orders)", k * f_rel))
    return out


def annotate_axes(
    ax: Any,
    markers: pd.DataFrame,
    unit: str = "order",
    kinds: Iterable[str] | None = None,
    label: bool = True,
    max_labels: int = 40,
) -> None:
    """Draw markers as vertical lines on a matplotlib axis whose x axis is ``unit``
    (``"order"`` or ``"hz"``); only markers within the current x limits are drawn."""
    if unit not in ("order", "hz"):
        raise InputError(f"unit: must be 'order' or 'hz', got {unit!r}")
    wanted = set(KINDS if kinds is None else kinds)
    bad = wanted - set(KINDS)
    if bad:
        raise InputError(f"kinds: unknown marker kinds {sorted(bad)}; known: {list(KINDS)}")
    lo, hi = ax.get_xlim()
    sel = markers[markers["kind"].isin(wanted) & markers[unit].between(lo, hi)]
    ytop = ax.get_ylim()[1]
    for i, (_, r) in enumerate(sel.iterrows()):
        ax.axvline(r[unit], color=_COLORS[r["kind"]], lw=0.7, ls="--", alpha=0.7)
        if label and i < max_labels and r["kind"] != "sideband":
            ax.text(
                r[unit],
                ytop,
                r["label"],
                rotation=90,
                fontsize=6,
                va="top",
                ha="right",
                color=_COLORS[r["kind"]],
            )
