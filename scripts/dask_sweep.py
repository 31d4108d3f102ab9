#!/usr/bin/env python3
"""Run an `airring sweep` study on a Dask distributed cluster: one task per run-up.

    dask_sweep.py STUDY.toml --out DIR [--scheduler tcp://host:8786] [--workers 2] [--airring PATH]

The grid comes from `airring sweep STUDY --list` (the same expansion, names and order as
`airring sweep`). Each task runs `airring runup <flags> --out DIR/runs/NAME --quiet` on a worker and
returns the run's summary.json; the run folders are laid out exactly as `airring sweep` lays them
out (sweep_run.json, summary.json, runup.log), so the study is resumable (completed runs with the same
flags are skipped), and at the end `airring sweep-merge DIR` writes DIR/study.csv and the bifurcation
maps, the same table as `airring sweep`.

Without --scheduler a LocalCluster is started with --workers single-threaded workers (default: half
the cores; each run-up uses two threads). With --scheduler, DIR must be on a file system the workers
share, and `airring` and the FMUs must exist at the same paths on every worker (or pass --airring and
--fmu-dir paths valid there).
"""
from __future__ import annotations

import argparse
import json
import os
import pathlib
import subprocess
import sys
import time


def plan(airring: str, study: str) -> list[dict]:
    r = subprocess.run([airring, "sweep", study, "--list"], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"airring sweep --list failed:\n{r.stderr}")
    return [json.loads(line) for line in r.stdout.splitlines() if line.strip()]


def is_done(run_dir: pathlib.Path, args: dict) -> bool:
    try:
        summary = json.loads((run_dir / "summary.json").read_text())
        meta = json.loads((run_dir / "sweep_run.json").read_text())
    except (OSError, ValueError):
        return False
    return summary.get("status") == "completed" and meta.get("args") == args


def run_one(airring: str, out: str, run: dict, fmu_dir: str | None, cwd: str | None) -> dict:
    """One grid point on a worker: the run-up, its log, and its summary (a failure summary if none)."""
    run_dir = pathlib.Path(out) / "runs" / run["name"]
    run_dir.mkdir(parents=True, exist_ok=True)
    summary_path = run_dir / "summary.json"
    if summary_path.exists():
        summary_path.unlink()
    meta = {"name": run["name"], "index": run["index"], "args": run["args"]}
    (run_dir / "sweep_run.json").write_text(json.dumps(meta, indent=2))
    # The sweep owns its run folders: a failed or stale run there is replaced.
    cmd = [airring, *run["argv"], "--out", str(run_dir), "--quiet", "--overwrite"]
    if fmu_dir and "fmu_dir" not in run["args"]:
        cmd += ["--fmu-dir", fmu_dir]
    start = time.time()
    with open(run_dir / "runup.log", "w") as log:
        p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=log, cwd=cwd)
    if not summary_path.exists():
        summary_path.write_text(json.dumps({
            "status": "failed",
            "error": f"the run-up ended with exit code {p.returncode} and wrote no summary; see runup.log",
            "classification": None, "onset_time_s": None, "max_eps_C": None, "max_eps_T": None,
            "wall_time_s": time.time() - start,
        }, indent=2))
    summary = json.loads(summary_path.read_text())
    return {"name": run["name"], "status": summary.get("status"), "classification": summary.get("classification"),
            "onset_speed_hz": summary.get("onset_speed_hz"), "wall_time_s": summary.get("wall_time_s"),
            "host": os.uname().nodename}


def parse_shard(text: str) -> tuple[int, int]:
    """`k/n` with 1 <= k <= n, as `airring sweep --shard`."""
    try:
        k, n = (int(x) for x in text.split("/"))
    except ValueError:
        raise SystemExit(f"--shard expects k/n with 1 <= k <= n, found '{text}'")
    if not 1 <= k <= n:
        raise SystemExit(f"--shard expects k/n with 1 <= k <= n, found '{text}'")
    return k, n


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("study", help="study file (TOML) as for `airring sweep`")
    ap.add_argument("--out", required=True, help="output folder (shared by the workers)")
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (default: a LocalCluster)")
    ap.add_argument("--workers", type=int, default=max(1, (os.cpu_count() or 2) // 2),
                    help="LocalCluster workers (default: half the cores)")
    ap.add_argument("--airring", default=os.environ.get("AIRRING", "airring"), help="the airring executable")
    ap.add_argument("--fmu-dir", help="folder with rotor.fmu and airfilm.fmu (default: airring's)")
    ap.add_argument("--shard", help="only the runs of shard k/n (as `airring sweep --shard`)")
    a = ap.parse_args(argv)
    if a.shard:
        parse_shard(a.shard)  # a bad --shard stops here, before any cluster starts

    from dask.distributed import Client, LocalCluster, as_completed

    airring = str(pathlib.Path(a.airring).resolve()) if os.sep in a.airring else a.airring
    out = pathlib.Path(a.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    (out / "study.toml").write_text(pathlib.Path(a.study).read_text())
    runs = plan(airring, a.study)
    if a.shard:
        k, n = parse_shard(a.shard)
        runs = [r for r in runs if r["index"] % n == k - 1]
    todo = [r for r in runs if not is_done(out / "runs" / r["name"], r["args"])]
    print(f"dask sweep: {len(runs)} runs, {len(runs) - len(todo)} already completed, {len(todo)} to run",
          file=sys.stderr)
    fmu_dir = str(pathlib.Path(a.fmu_dir).resolve()) if a.fmu_dir else None
    # Workers start the run-ups here (relative fmu_dir paths in the study resolve against it) on
    # a LocalCluster; remote workers keep their own working folder unless it exists for them.
    cwd = os.getcwd() if not a.scheduler else None

    cluster = None
    if a.scheduler:
        client = Client(a.scheduler)
    else:
        cluster = LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    failed = []
    try:
        futures = [client.submit(run_one, airring, str(out), r, fmu_dir, cwd, key=f"runup-{r['name']}", pure=False)
                   for r in todo]
        names = {f.key: r["name"] for f, r in zip(futures, todo)}
        for i, f in enumerate(as_completed(futures), 1):
            try:
                res = f.result()
            except Exception as e:  # a worker-side failure (airring missing, folder not shared, ...)
                # Record it as the run's failure and go on: the other runs and the merge still count.
                name = names[f.key]
                run_dir = out / "runs" / name
                try:
                    run_dir.mkdir(parents=True, exist_ok=True)
                    (run_dir / "summary.json").write_text(json.dumps({
                        "status": "failed", "error": f"the Dask task failed: {e!r}",
                        "classification": None, "onset_time_s": None, "max_eps_C": None,
                        "max_eps_T": None, "wall_time_s": None,
                    }, indent=2))
                except OSError:
                    pass
                res = {"name": name, "status": "failed", "classification": None,
                       "onset_speed_hz": None, "wall_time_s": None, "host": "?"}
                print(f"dask sweep: {name}: task failed: {e!r}", file=sys.stderr)
            if res["status"] != "completed":
                failed.append(res["name"])
            print(f"[{i}/{len(todo)}] {res['name']} on {res['host']}: {res['status']}, {res['classification']}, "
                  f"onset {res['onset_speed_hz']} Hz, {res['wall_time_s']} s", file=sys.stderr)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()

    r = subprocess.run([airring, "sweep-merge", str(out)], capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stderr, file=sys.stderr)
        return 1
    print(f"dask sweep: {len(todo)} run, {len(failed)} failed -> {out / 'study.csv'}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
