#!/usr/bin/env python3
"""Killed and resumed: a study and a damper run, killed with SIGKILL at random moments and
resumed each time, must end with the records of an uninterrupted run (issue 25; docs/studies.md,
"Resuming").

usage: kill_resume.py [--vppdem build/vppdem] [--out DIR] [--kills N] [--seed S]
                      [--only sweep|damper|stages]

sweep:  a small study (the tests' small damper: 2 frictions x 2 seeds, one preparation per seed,
        2 cycles) runs once without interruption (the reference), then again into another folder,
        killed after a random delay and restarted with the same command, until it finishes; rounds
        repeat from an empty folder until N kills (default 20) have been survived.
damper: the same for `vppdem damper` on the small damper: killed, then resumed from its
        run.ckpt (or, killed before the first one, started again with --overwrite).
stages: the small damper once more, checkpointing only where a run must (at the start of each
        stage and after each re-fill; --checkpoint-every far beyond the run), every version of its
        run.ckpt kept as it appears; each is then resumed in a folder of its own. A random kill
        seldom lands right after such a checkpoint (the next periodic one comes 0.05 s later), yet
        these are the states a run changes by hand before its next step (grains added, the funnel
        gone): the kill that lands there must resume too.
Checkpoints every 0.05 s of wall clock (--checkpoint-every) so that kills land in checkpoint
writes too; the reference keeps the default (60 s): checkpointing must not change a result.
Each kill is classed by what the folder held at that moment: `preparation` (a started case
without prepared.ckpt), `write` (a *.part file: a checkpoint, record or summary being written),
`cycling` (otherwise), `start` (nothing written yet).

Compared at the end of each round, byte for byte: every case's forces.csv, cycles.csv,
energy.csv, summary.json and the study's summary.csv, summary_cases.csv, summary_paired.csv,
except the wall-clock fields (`run_seconds` in summary.json and in summary.csv) and summary.json's
`from` (the checkpoint a resumed run continued from), which are removed before the comparison; every case must be there once (no case missing, none twice).
Prints one line per kill and a table; exits 1 at the first difference (naming the file), 0 when
every round matched. Delays are drawn from a seeded generator (--seed), so a failing sequence
of kills can be replayed. Runs under /usr/bin/python3 (numpy, which the package vppdem needs).
"""
import argparse
import csv
import io
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time

# The package's records (vppdem/records.py): one CSV reader and one way to stop for the tools.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "src", "python"))
from vppdem.records import fail, read_table  # noqa: E402

SMALL = ["--set", "damper.radius=0.012", "--set", "damper.height=0.03", "--set", "grains.volume_fraction=0.45",
         "--set", "process.velocity=0.1", "--set", "process.amplitude=0.002", "--set", "process.samples_per_cycle=40",
         "--set", "simulation.threads=1",
         # The tests' step and mass scaling (tests/physics/cli_helpers.h, kSmallDamper): resuming is
         # checked, not the step's convergence or the grains' inertia (densities 100 times the
         # paper's: a step 10 times longer, a run about 5 times quicker).
         "--set", "simulation.dt_safety=0.45", "--set", "grains.density=268963.9", "--set", "foil.density=15177"]
# The study: the same small damper (its [set] made from SMALL), 2 cycles, 2 frictions x 2 seeds.
STUDY = ('description = "kill_resume.py: small damper, 2 frictions x 2 seeds"\nseeds = 2\n\n[set]\n' +
         "".join(f'"{kv.split("=")[0]}" = {kv.split("=")[1]}\n' for kv in SMALL[1::2]) +
         '"process.cycles" = 2\n\n[grid]\n"grains.friction" = [0.3, 0.6]\n')
RECORDS = ["forces.csv", "cycles.csv", "energy.csv", "summary.json"]
TABLES = ["summary.csv", "summary_cases.csv", "summary_paired.csv"]


def without_clock(path):
    """The file's bytes, with the wall-clock fields removed (they differ between any two runs)."""
    with open(path, "rb") as f:
        data = f.read()
    name = os.path.basename(path)
    if name == "summary.json":
        js = json.loads(data)
        js.pop("run_seconds", None)
        js.pop("from", None)  # the checkpoint a resumed run continued from: provenance, not a result
        return json.dumps(js, sort_keys=True).encode()
    if name == "summary.csv":
        rows = list(csv.reader(io.StringIO(data.decode())))
        if rows and "run_seconds" in rows[0]:
            k = rows[0].index("run_seconds")
            rows = [r[:k] + r[k + 1:] for r in rows]
        return "\n".join(",".join(r) for r in rows).encode()
    return data


def compare(ref, got, names):
    """Every record and table of the reference folder, equal in the other; no extra case."""
    cases_ref = sorted(d for d in os.listdir(ref) if os.path.isdir(os.path.join(ref, d)) and d != "vtk")
    cases_got = sorted(d for d in os.listdir(got) if os.path.isdir(os.path.join(got, d)) and d != "vtk")
    if cases_ref != cases_got:
        fail(f"case folders differ: {cases_ref} against {cases_got}")
    for c in [""] + cases_ref:
        for n in names if c == "" else RECORDS:
            a, b = os.path.join(ref, c, n), os.path.join(got, c, n)
            if os.path.exists(a) != os.path.exists(b):
                fail(f"{os.path.join(c, n)}: in one run only ({a if os.path.exists(a) else b})")
            if os.path.exists(a) and without_clock(a) != without_clock(b):
                fail(f"{os.path.join(c, n)} differs from the uninterrupted run ({a} against {b})")
    if "summary.csv" in names:
        _, rows = read_table(os.path.join(got, "summary.csv"))
        cases = [r["case"] for r in rows]
        if len(cases) != len(set(cases)) or sorted(cases) != cases_ref:
            fail(f"summary.csv lists {cases}, the study has {cases_ref}")
        if any(r["status"] != "ok" for r in rows):
            fail("summary.csv: a case did not end ok")


def moment(folder, single):
    """What the folder held when the kill came (single: the folder is one run's, not a study's)."""
    part = started = unprepared = False
    for root, _, files in os.walk(folder):
        if any(f.endswith(".part") or ".part." in f for f in files):
            part = True
        if {"forces.csv", "prepared.ckpt", "case.toml", "run.ckpt"} & set(files):
            started = True
            if "prepared.ckpt" not in files and "summary.json" not in files and (single or root != folder):
                unprepared = True
    if part:
        return "write"
    if not started:
        return "start"
    return "preparation" if unprepared else "cycling"


def newest(folder):
    t = 0.0
    for root, _, files in os.walk(folder):
        for f in files:
            try:
                t = max(t, os.stat(os.path.join(root, f)).st_mtime)
            except FileNotFoundError:
                pass
    return t


def run_killed(commands, folder, delay_max, rng, log, tally, single):
    """Runs commands(folder) (a function giving the command for the folder's state) until it
    exits 0, killing it after a random delay each time; returns the kills. A kill before the run
    wrote anything new (the start-up, a checkpoint load, took longer than the delay) makes the
    next delays longer, so that every round ends."""
    kills = 0
    while True:
        cmd = commands(folder)
        before = newest(folder)
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)
        delay = rng.uniform(0.01, delay_max)
        try:
            _, err = p.communicate(timeout=delay)
            if p.returncode != 0:
                fail(f"{' '.join(cmd)} failed ({p.returncode}) after {kills} kills: {err.decode()[-2000:]}")
            return kills
        except subprocess.TimeoutExpired:
            where = moment(folder, single)
            os.killpg(p.pid, signal.SIGKILL)
            p.communicate()
            kills += 1
            tally[where] = tally.get(where, 0) + 1
            if newest(folder) <= before:
                delay_max *= 1.5
            log(f"  kill {kills:3d} after {delay:6.3f} s ({where})")


def resume_every_checkpoint(vppdem, ref, out, base, log):
    """Runs `base` (the damper's reference command) into out/watched with checkpoints only where
    the run forces them, keeping each version of its run.ckpt as it appears; resumes each in a
    folder of its own. Every one must end with the reference's records; returns how many."""
    watched = os.path.join(out, "watched")
    os.makedirs(out)
    cmd = [c if c != ref else watched for c in base] + ["--checkpoint-every", "1e6"]
    ck, seen, kept = os.path.join(watched, "run.ckpt"), set(), []
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)
    while True:
        running = p.poll() is None
        try:
            # A checkpoint arrives by rename: the file opened is a whole one, old or new.
            with open(ck, "rb") as f:
                st = os.fstat(f.fileno())
                key = (st.st_ino, st.st_mtime_ns, st.st_size)
                if key not in seen:
                    seen.add(key)
                    kept.append(os.path.join(out, f"{len(kept) + 1:02d}.ckpt"))
                    with open(kept[-1], "wb") as g:
                        shutil.copyfileobj(f, g)
        except FileNotFoundError:
            pass
        if not running:
            break
        time.sleep(0.002)
    if p.wait() != 0:
        fail(f"{' '.join(cmd)} failed ({p.returncode}): {p.stderr.read().decode()[-2000:]}")
    compare(ref, watched, [])
    log(f"stages: {len(kept)} checkpoints written where the run forces them")
    for k, snap in enumerate(kept, 1):
        folder = os.path.join(out, f"resumed_{k:02d}")
        os.makedirs(folder)
        shutil.copy(snap, os.path.join(folder, "run.ckpt"))
        r = subprocess.run([vppdem, "damper", "--out", folder, "--from", os.path.join(folder, "run.ckpt"),
                            "--no-plot", "--quiet"], capture_output=True)
        if r.returncode != 0:
            fail(f"resuming the run's checkpoint {k} of {len(kept)} ({snap}) failed ({r.returncode}): "
                 f"{r.stderr.decode()[-2000:]}")
        compare(ref, folder, [])
        log(f"  checkpoint {k:2d}: resumed, records equal to the uninterrupted run")
        shutil.rmtree(folder)
    return len(kept)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--vppdem", default="build/vppdem")
    ap.add_argument("--out", default="out/kill_resume")
    ap.add_argument("--kills", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--only", choices=["sweep", "damper", "stages"])
    a = ap.parse_args()
    sys.stdout.reconfigure(line_buffering=True)
    if a.kills < 1:
        fail(f"--kills = {a.kills}: must be at least 1")
    vppdem = os.path.abspath(a.vppdem)
    if not os.access(vppdem, os.X_OK):
        fail(f"no vppdem binary at {a.vppdem} (build it: bash scripts/build.sh vppdem)")
    rng = random.Random(a.seed)
    shutil.rmtree(a.out, ignore_errors=True)
    os.makedirs(a.out)
    study = os.path.join(a.out, "study.toml")
    with open(study, "w") as f:
        f.write(STUDY)
    results, refs = [], {}  # refs: what -> (uninterrupted run's folder, its seconds)
    for what in ["sweep", "damper", "stages"] if a.only is None else [a.only]:
        if what == "sweep":
            def cmd(folder, every=True):
                return [vppdem, "sweep", study, "--out", folder, "--jobs", "1", "--no-plot", "--quiet"] + (
                    ["--checkpoint-every", "0.05"] if every else [])
            names = TABLES
        else:  # damper, stages
            def cmd(folder, every=True):
                base = [vppdem, "damper", "--out", folder, "--no-plot", "--quiet"] + SMALL + [
                    "--set", "process.cycles=2"] + (["--checkpoint-every", "0.05"] if every else [])
                ck = os.path.join(folder, "run.ckpt")
                if every and os.path.exists(ck):
                    return [vppdem, "damper", "--out", folder, "--from", ck, "--no-plot", "--quiet",
                            "--checkpoint-every", "0.05"]
                return base + (["--overwrite"] if every and os.path.isdir(folder) else [])
            names = []
        if what == "stages" and "damper" in refs:
            ref, t_ref = refs["damper"]  # the same run as the damper's reference: made once
        else:
            ref = os.path.join(a.out, what + "_reference")
            t0 = time.monotonic()
            r = subprocess.run(cmd(ref, every=False), capture_output=True)
            if r.returncode != 0:
                fail(f"the reference {what} failed: {r.stderr.decode()[-2000:]}")
            t_ref = time.monotonic() - t0
            print(f"{what}: uninterrupted run {t_ref:.1f} s")
        refs[what] = (ref, t_ref)
        if what == "stages":
            n = resume_every_checkpoint(vppdem, ref, os.path.join(a.out, "stages"), cmd(ref, every=False), print)
            results.append((what, n, 1, {"stage start": n}, t_ref))
            continue
        kills, rounds, tally = 0, 0, {}
        while kills < a.kills:
            rounds += 1
            folder = os.path.join(a.out, f"{what}_killed_{rounds}")
            print(f"{what}, round {rounds}:")
            # About as many kills per round as asked for, each a random share of the run.
            k = run_killed(lambda f: cmd(f), folder, 2.0 * t_ref / a.kills, rng, print, tally, what == "damper")
            compare(ref, folder, names)
            kills += k
            print(f"  {k} kills, records equal to the uninterrupted run")
            shutil.rmtree(folder)
        results.append((what, kills, rounds, tally, t_ref))
    print("\n| run | kills survived | rounds | at the kill: start / preparation / cycling / write | uninterrupted [s] |")
    print("|---|---|---|---|---|")
    for what, kills, rounds, tally, t_ref in results:
        if what == "stages":
            print(f"| stages | {kills} (one per forced checkpoint) | {rounds} | right after a forced checkpoint | {t_ref:.1f} |")
            continue
        print(f"| {what} | {kills} | {rounds} | {tally.get('start', 0)} / {tally.get('preparation', 0)} / "
              f"{tally.get('cycling', 0)} / {tally.get('write', 0)} | {t_ref:.1f} |")
    print("every round ended with the records of the uninterrupted run (wall-clock fields aside)")


if __name__ == "__main__":
    main()
