"""Detectability curves of a Wang 2010 fault data set (examples/sweeps/seed004_fault_dataset.toml
or its quick version examples/sweeps/quick_crack_set.toml): FM4 of the cracked member (sun,
ring, planet 1: those of the data set) against crack size, mean ± 1 std over the replicates,
one panel per motor speed; the healthy cases (crack 0) start every curve. Prints the detection
rate (verdict 'alarm' on the cracked member) per gear and severity.

    geardyn sweep examples/sweeps/seed004_fault_dataset.toml --out seed004_faults.zarr
    python examples/sweeps/plot_detectability.py seed004_faults.zarr sweep_detectability.png
"""

from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")  # a script writing a file
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import geardyn  # noqa: E402
from geardyn.sweep import plot_detectability  # noqa: E402

MEMBER = {"sun": "planetary.sun", "ring": "planetary.ring", "planet": "planetary.planet1/z32"}


def main(store: str, png: str, indicator: str = "FM4") -> None:
    ds = geardyn.open_dataset(store).load()
    speeds = [float(s) for s in np.unique(ds["motor_speed_rpm"].values)]
    members = {g: c for g, c in MEMBER.items() if g in set(ds["fault_gear"].values)}
    fig, axes = plt.subplots(len(members), len(speeds), squeeze=False, sharex=True,
                             figsize=(5 * len(speeds), 3.2 * len(members)))
    for r, (gear, comp) in enumerate(members.items()):
        for c, rpm in enumerate(speeds):
            sub = ds.isel(case=np.flatnonzero((ds["motor_speed_rpm"].values == rpm)
                                              & np.isin(ds["fault_gear"].values, ["none", gear])))
            plot_detectability(sub, comp, indicator, "crack_fraction", by=["fault_gear"],
                               healthy={"fault_gear": "none"}, ax=axes[r, c])
            axes[r, c].set_title(f"{gear} crack, motor {rpm:g} rpm", fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print(f"wrote {png}")
    if "verdict" in ds:
        print("detection rate (verdict 'alarm' on the cracked member) per motor speed:")
        for gear, comp in members.items():
            for rpm in speeds:
                rates = []
                for sev in sorted(np.unique(ds["crack_fraction"].values)):
                    sel = ((ds["motor_speed_rpm"].values == rpm)
                           & (ds["crack_fraction"].values == sev)
                           & np.isin(ds["fault_gear"].values, [gear] if sev > 0 else ["none"]))
                    v = ds["verdict"].sel(component=comp).values[sel]
                    rates.append(f"{sev:g}: {np.sum(v == 'alarm')}/{v.size}")
                print(f"  {gear:6s} {rpm:6g} rpm  " + "  ".join(rates))


if __name__ == "__main__":
    main(*sys.argv[1:3], *(sys.argv[3:4]))
