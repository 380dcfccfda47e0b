"""Solvers for lumped-parameter models: modal analysis (:mod:`.modal`) and time integration
(:mod:`.integrate`, numba-compiled Newmark/HHT-α with a generic M, C, K(t) interface)."""
