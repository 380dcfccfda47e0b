"""Heavy tails of healthy fleets and the family floor (issue 18, false alarms).

For every planetary configuration of one half of a detectability study folder (the study's
cached 6-run baselines, ``python -m geardyn.studies.detectability --out STUDY``), this script
judges against runs 0-5:

* six more runs drawn exactly as the baseline's own (seeds 6-11, the same generator, two
  measurements each; cached in WORK),
* four fresh fleet records with run seeds of their own,
* cracks of 10 and 20 % on the sun, the ring and planet 1 (the first fresh record's machine),

once with the family floor and once without (``[diagnosis] family_floor``), and prints the
alarms per item kind. Numbers of 2026-11-26 (tune half, 9 configurations): docs/diagnosis.md,
known limitations.

Run: ``PYTHONPATH=src python experiments/detectability_tails.py STUDY WORK [tune|report]``
(about 25 CPU minutes for the tune half).
"""

from __future__ import annotations

import collections
import glob
import json
import pickle
import sys
from pathlib import Path


def main(study: str, work: str, half: str = "tune") -> None:
    from geardyn.config.loader import parse_config
    from geardyn.diagnosis import pipeline as pipe
    from geardyn.diagnosis.ensemble import simulate_baseline
    from geardyn.run import run_simulation
    from geardyn.sweep.diagnosis import record
    from geardyn.sweep.spec import load_spec, set_path

    Path(work).mkdir(parents=True, exist_ok=True)
    counts: dict[tuple[str, bool], list[int]] = collections.defaultdict(lambda: [0, 0])
    seen: set[str] = set()
    for toml in sorted(glob.glob(f"{study}/planetary*.toml")):
        sw = load_spec(toml)
        diag = sw.spec.outputs.diagnosis.model_dump()
        for case in sw.cases:
            lab = case.labels(sw.axes)
            conf = str(lab["configuration"])
            if lab["record"] != "healthy" or lab["half"] != half or conf in seen:
                continue
            seen.add(conf)
            cfg = parse_config(sw.case_config(case))
            rec0 = record(cfg, 0, {}, diag)
            cache = Path(toml).with_suffix(".zarr") / "diagnosis_cache"
            with open(cache / f"baseline-{rec0.baseline_key}.pkl", "rb") as fh:
                base = pickle.load(fh)  # noqa: S301 - the study's own cache
            extra = Path(work) / f"extra-{rec0.baseline_key}.pkl"
            if not extra.exists():
                opts = rec0.opts.model_copy(update={"baseline_seeds": list(range(6, 12))})
                feats, blocks = [], []
                for member, ds in simulate_baseline(rec0.healthy, opts, rec0.run_length):
                    ch = pipe._channel(ds, opts.channel, "member")
                    feats.append(pipe._features(ds, rec0.healthy, ch, opts))
                    b = pipe._blocks(ds, rec0.healthy, ch, opts).compact()
                    b.run = member.run + 6
                    blocks.append(b)
                with open(extra, "wb") as fh:
                    pickle.dump({"features": feats, "blocks": blocks}, fh)
            with open(extra, "rb") as fh:
                ext = pickle.load(fh)  # noqa: S301 - written above
            items = [("extra run", f, b) for f, b in zip(ext["features"], ext["blocks"],
                                                          strict=True)]
            first = 200 + 4 * int(conf.split("-")[1]) + (100 if conf.startswith("pl4") else 0)
            runs = [("fresh record", cfg, first + k) for k in range(4)]
            data = cfg.model_dump(mode="json")
            for gear in ("sun", "ring", "planet"):
                for c in (0.1, 0.2):
                    d = json.loads(json.dumps(data))
                    fault = {"kind": "crack", "gear": gear, "crack_fraction": c}
                    if gear == "planet":
                        fault["planet"] = 1
                    set_path(d, "planetary_dynamics.stages[0].faults", [fault])
                    runs.append((f"{gear} crack {c:.0%}", parse_config(d), first))
            for kind, c2, seed in runs:
                rec = record(c2, seed, {}, diag)
                ds = run_simulation(rec.config, seed=rec.run_seed,
                                    **{k: v for k, v in rec.run_length.items() if v is not None})
                ch = pipe._channel(ds, rec.opts.channel, "record")
                items.append((kind, pipe._features(ds, rec.config, ch, rec.opts),
                              pipe._blocks(ds, rec.config, ch, rec.opts).compact()))
            for kind, f, b in items:
                for pool in (False, True):
                    opts = rec0.opts.model_copy(update={"family_floor": pool})
                    v = pipe.judge_features(rec0.healthy, opts, base["features"], f,
                                            baseline_blocks=base["blocks"], record_blocks=b,
                                            expected=[])
                    n = counts[(kind, pool)]
                    n[0] += 1
                    n[1] += int(bool((v.detection or {}).get("detected")))
            print(conf, "done", flush=True)
    print(f"{'item':16s} {'n':>4s} {'alarms, own spreads':>20s} {'with the family floor':>22s}")
    for kind in sorted({k for k, _ in counts}):
        n, a = counts[(kind, False)]
        print(f"{kind:16s} {n:4d} {a:20d} {counts[(kind, True)][1]:22d}")


if __name__ == "__main__":
    main(*sys.argv[1:])
