"""Diagnosis: machine components from kinematics, features and condition indicators per
component, healthy baselines, thresholds, verdicts and the HTML report."""
