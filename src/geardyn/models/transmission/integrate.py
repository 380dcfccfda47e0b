"""Re-export of the FE transmission's explicit integrator, now :mod:`geardyn.solve.explicit`
(issue 12: the integrators live in one ``solve`` package)."""

from geardyn.solve.explicit import (  # noqa: F401 - re-exports
    E_EXT,
    E_FRIC,
    E_IN,
    E_MODAL,
    E_OUT,
    E_ROLL,
    E_SQZ,
    E_VISC,
    STATE,
    applied_loads,
    csr,
    gyroscopic_args,
    gyroscopic_forces,
    no_gyroscopic,
    no_loads,
    record,
    ref_sign_speed,
    run_chunk,
    run_loop,
    stable_time_step,
    start_loop,
)
