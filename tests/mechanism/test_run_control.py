"""The general [dynamics] model under the run machinery of issue 13: a stop request between
chunks keeps the computed part (status 'interrupted'), a too-large time step is refused before
the run naming dynamics.simulation.dt_s, and a sensor on an unknown shaft is refused before it."""

from __future__ import annotations

import pytest

from geardyn import load_config
from geardyn.errors import InputError
from geardyn.run import run_simulation
from geardyn.solve.control import RunControl

DIFF = "car_differential_dynamics.toml"


def test_stop_request_keeps_the_computed_part(examples_dir):
    cfg = load_config(examples_dir / DIFF)

    def progress(_f: float) -> None:
        ctl.request_stop("test stop")

    ctl = RunControl(progress=progress, chunk_wall_s=1e-4)
    full = run_simulation(cfg, t_end_s=0.2)
    part = run_simulation(cfg, t_end_s=0.2, control=ctl)
    assert full.attrs["status"] == "ok"
    assert part.attrs["status"] == "interrupted" and "test stop" in part.attrs["diagnosis"]
    n = part.sizes["time"]
    assert 1 < n < full.sizes["time"]
    # the computed part is the same run (exact chunks), not a restart
    assert (part["angle"].values == full["angle"].values[:n]).all()


def test_too_large_time_step_refused_naming_the_field(examples_dir):
    cfg = load_config(examples_dir / DIFF)
    sim = cfg.dynamics.simulation.model_copy(update={"dt_s": 0.05})
    big = cfg.model_copy(update={"dynamics": cfg.dynamics.model_copy(update={"simulation": sim})})
    with pytest.raises(InputError, match=r"dynamics\.simulation\.dt_s: the time step"):
        run_simulation(big, t_end_s=1.0)


def test_sensor_on_unknown_shaft_refused_before_the_run(examples_dir, monkeypatch):
    cfg = load_config(examples_dir / DIFF)
    from geardyn.config.sensors import SensorSpec

    bad = SensorSpec(name="enc", kind="encoder", shaft="propeller", pulses_per_rev=64)
    cfg = cfg.model_copy(update={"sensors": [bad]})

    def boom(*a, **k):
        raise AssertionError("the model ran before the sensor check")

    monkeypatch.setattr("geardyn.models.core.simulate.simulate", boom)
    with pytest.raises(InputError, match="'propeller' is not a shaft"):
        run_simulation(cfg, t_end_s=0.1)
