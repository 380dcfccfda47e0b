"""The issue-12 speed options through the run control: a stopped seed 002 run with lumped mass
and truncated modal damping resumes bit-identically (records written through the loop's block
buffer, chunk boundaries anywhere), and its checkpoint is refused by a run with the dense
damping (another loop set-up)."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.config.loader import load_config, parse_config
from geardyn.errors import InputError
from geardyn.solve.control import RunControl


def _stop_after_first_chunk() -> tuple[RunControl, list[dict]]:
    saved: list[dict] = []

    def progress(_f: float) -> None:
        ctl.request_stop("test stop")

    ctl = RunControl(progress=progress, checkpoint=lambda s: saved.append(
        {k: np.array(v, copy=True) if isinstance(v, np.ndarray) else v for k, v in s.items()}))
    return ctl, saved


def test_lumped_truncated_stop_and_resume_bit_identical(examples_dir) -> None:
    from geardyn.models.transmission import build_model, prepare, simulate

    d = load_config(examples_dir / "seed002_transmission.toml").model_dump(exclude_none=True)
    d["transmission"].update(mass="lumped", modal_damping_cutoff_hz=3000.0)
    cfg = parse_config(d)
    prep = prepare(build_model(cfg), "output")
    assert np.count_nonzero(prep.model.M - np.diag(np.diag(prep.model.M))) == 0
    full = simulate(cfg, revolutions=0.3, prepared=prep)
    assert full.attrs["status"] == "ok"
    ctl, saved = _stop_after_first_chunk()
    part = simulate(cfg, revolutions=0.3, prepared=prep, control=ctl)
    assert part.attrs["status"] == "interrupted"
    n = part.sizes["time"]
    assert 1 < n < full.sizes["time"]
    assert np.array_equal(part["bearing_force"].values, full["bearing_force"].values[:n])
    res = simulate(cfg, revolutions=0.3, prepared=prep, control=RunControl(resume=saved[-1]))
    for name in full.data_vars:
        assert np.array_equal(res[name].values, full[name].values), name
    for key in ("energy_input_J", "energy_modal_damping_J", "steps"):
        assert res.attrs[key] == full.attrs[key]
    # the same model with the dense modal damping is another run
    d["transmission"].pop("modal_damping_cutoff_hz")
    with pytest.raises(InputError, match="another run"):
        simulate(parse_config(d), revolutions=0.3, prepared=prep,
                 control=RunControl(resume=saved[-1]))
