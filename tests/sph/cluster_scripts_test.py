#!/usr/bin/env python3
"""The cluster scripts (scripts/cluster/) generate the same dataset as one process.

Usage: cluster_scripts_test.py SPILL_SIM SOURCE_DIR

On a tiny scene of 5 trajectories:
  - one `spill-sim generate` process makes the reference dataset;
  - generate_local.sh runs 2 shards side by side (xargs -P 2) into one folder: the last to finish
    assembles it, and its statistics, counts and trajectories equal the reference's;
  - submit_generation.sh, with a stand-in for Slurm's sbatch on PATH that runs an array's tasks
    with the SLURM_ARRAY_* variables Slurm sets (and refuses a job whose afterok dependency
    failed), submits 3 shards (the array 0-2) and the assembling job: the dataset again equals
    the reference, the array tasks ran with --shard left to the environment, and no temporary
    file is left;
  - river_small, 4 trajectories, as 3 shards side by side: train.h5, valid.h5 and test.h5 equal
    one process's (h5diff) and the metadata too, apart from wall times;
  - refusals: assembling a folder with a shard missing names the missing trajectories (exit 2);
    a shard of another request names the key that differs (exit 2); an array task id outside the
    array, --shard 3/3 and --shard given to the submit script exit 2.
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile

SCENE = {
    "name": "tiny", "particle_radius": 0.02, "end_time": 0.2, "output": {"frame_dt": 0.02},
    "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2], "velocity": [0, 0, 0]}],
}

# Runs a script's array tasks in order with Slurm's variables, and a dependent job only when
# every job it depends on (afterok) exited 0. Job ids count up from 100; exit codes are kept in
# $FAKE_SLURM_DIR/<id>.rc.
FAKE_SBATCH = r"""#!/usr/bin/env bash
set -u
state="$FAKE_SLURM_DIR"
id=$(( $(ls "$state" | grep -c '\.rc$') + 100 ))
array=""; dependency=""
while [[ $# -gt 0 && "$1" == --* ]]; do
  case "$1" in
    --array=*) array="${1#--array=}" ;;
    --dependency=*) dependency="${1#--dependency=}" ;;
  esac
  shift
done
script=$1; shift
if [[ -n "$dependency" ]]; then
  dep=${dependency#afterok:}
  if [[ "$(cat "$state/$dep.rc")" != 0 ]]; then echo 1 > "$state/$id.rc"; echo "$id"; exit 0; fi
fi
rc=0
if [[ -n "$array" ]]; then
  lo=${array%-*}; hi=${array#*-}
  for ((t = lo; t <= hi; ++t)); do
    SLURM_ARRAY_JOB_ID=$id SLURM_ARRAY_TASK_ID=$t SLURM_ARRAY_TASK_MIN=$lo \
      SLURM_ARRAY_TASK_MAX=$hi SLURM_ARRAY_TASK_COUNT=$((hi - lo + 1)) \
      bash "$script" "$@" >> "$state/$id.log" 2>&1 || rc=1
  done
else
  bash "$script" "$@" >> "$state/$id.log" 2>&1 || rc=1
fi
echo $rc > "$state/$id.rc"
echo "$id"
"""

failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


def run(command, env=None, expect=0):
    p = subprocess.run(command, env=env, capture_output=True, text=True, timeout=600)
    if p.returncode != expect:
        failures.append(f"{' '.join(command)}: exit {p.returncode}, expected {expect}")
        print(p.stdout, p.stderr, file=sys.stderr)
    return p


def comparable(metadata):
    """The statistics, counts and trajectories' descriptions, without their wall times."""
    keys = ["vel_mean", "vel_std", "acc_mean", "acc_std", "counts", "sequence_lengths",
            "trajectories"]
    out = {k: metadata[k] for k in keys}
    for t in out["trajectories"]:
        t.pop("sph_seconds_per_frame", None)
        t.pop("sph_wall_s", None)
    return out


def main():
    sim, source = os.path.abspath(sys.argv[1]), sys.argv[2]
    cluster = os.path.join(source, "scripts", "cluster")
    work = tempfile.mkdtemp(prefix="spill_cluster_")
    try:
        scene = os.path.join(work, "tiny.json")
        with open(scene, "w") as f:
            json.dump(SCENE, f)
        request = ["--scene", scene, "--trajectories", "5", "--seed", "3", "--frames", "5",
                   "--split", "0.6/0.2/0.2", "--vary", "/fluid_blocks/0/velocity/0=0:1"]
        env = dict(os.environ, SPILL_SIM=sim, OMP_NUM_THREADS="1")
        for k in [k for k in env if k.startswith("SLURM_")]:
            del env[k]

        reference_dir = os.path.join(work, "reference")
        run([sim, "generate", *request, "--out", reference_dir], env)
        with open(os.path.join(reference_dir, "metadata.json")) as f:
            reference = comparable(json.load(f))

        # Two shards side by side on this machine.
        local_dir = os.path.join(work, "local")
        run(["bash", os.path.join(cluster, "generate_local.sh"), "2", *request, "--out",
             local_dir], env)
        with open(os.path.join(local_dir, "metadata.json")) as f:
            check(comparable(json.load(f)) == reference, "generate_local.sh: metadata differs")

        # Three shards as a Slurm array and the dependent assembling job.
        bin_dir, state = os.path.join(work, "bin"), os.path.join(work, "slurm")
        os.makedirs(bin_dir)
        os.makedirs(state)
        with open(os.path.join(bin_dir, "sbatch"), "w") as f:
            f.write(FAKE_SBATCH)
        os.chmod(os.path.join(bin_dir, "sbatch"), 0o755)
        slurm_env = dict(env, PATH=bin_dir + os.pathsep + env["PATH"], FAKE_SLURM_DIR=state)
        slurm_dir = os.path.join(work, "slurm_dataset")
        p = run(["bash", os.path.join(cluster, "submit_generation.sh"), "3", *request, "--out",
                 slurm_dir], slurm_env)
        check("shards: job 100 (array 0-2); assemble: job 101" in p.stdout,
              f"submit_generation.sh printed {p.stdout!r}")
        for job in ("100", "101"):
            with open(os.path.join(state, job + ".rc")) as f:
                check(f.read().strip() == "0", f"job {job} failed")
        with open(os.path.join(state, "100.log")) as f:
            shard_log = f.read()
        check(shard_log.count("shard 0/3: simulated 2 trajectories") == 1,
              "array task 0 did not simulate trajectories 0 and 3:\n" + shard_log)
        check(shard_log.count("shard 1/3: simulated 2 trajectories") == 1,
              "array task 1 did not simulate trajectories 1 and 4:\n" + shard_log)
        check("wrote" in shard_log, "the last array task did not assemble:\n" + shard_log)
        with open(os.path.join(slurm_dir, "metadata.json")) as f:
            check(comparable(json.load(f)) == reference, "Slurm array: metadata differs")
        for folder in (slurm_dir, os.path.join(slurm_dir, "parts"), local_dir):
            left = [n for n in os.listdir(folder) if ".tmp" in n]
            check(not left, f"temporaries left in {folder}: {left}")

        # The small river, 4 trajectories, as 3 shards side by side: the split files equal one
        # process's (h5diff), and so does the metadata apart from wall times.
        river = ["--scene", os.path.join(source, "configs", "scenes", "river_small.json"),
                 "--trajectories", "4", "--frames", "8", "--split", "0.5/0.25/0.25", "--seed",
                 "5", "--vary", "/leaks/0/rate=0.002:0.005"]
        river_one, river_shards = os.path.join(work, "river_one"), os.path.join(work, "river3")
        run([sim, "generate", *river, "--out", river_one], env)
        run(["bash", os.path.join(cluster, "generate_local.sh"), "3", *river, "--out",
             river_shards], env)
        for split in ("train.h5", "valid.h5", "test.h5"):
            p = run(["h5diff", os.path.join(river_one, split), os.path.join(river_shards, split)])
            check(p.returncode == 0, f"h5diff {split}: {p.stdout[-500:]}")
        with open(os.path.join(river_one, "metadata.json")) as f:
            one = json.load(f)
        with open(os.path.join(river_shards, "metadata.json")) as f:
            three = json.load(f)
        for meta in (one, three):
            for t in meta["trajectories"]:
                t.pop("sph_seconds_per_frame", None)
                t.pop("sph_wall_s", None)
        check(one == three, "river_small: the sharded metadata differs (apart from wall times)")

        # Refusals.
        partial = os.path.join(work, "partial")
        run([sim, "generate", *request, "--out", partial, "--shard", "1/2"], env)
        p = run([sim, "generate", "--assemble", "--out", partial], env, expect=2)
        check("00000, 00002, 00004" in p.stderr, f"missing trajectories not named: {p.stderr}")
        check(not os.path.exists(os.path.join(partial, "metadata.json")),
              "a partial dataset was assembled")
        other = [a if a != "3" else "4" for a in request]  # --seed 4
        p = run([sim, "generate", *other, "--out", partial, "--shard", "0/2"], env, expect=2)
        check("/seed" in p.stderr, f"another request's shard not refused by key: {p.stderr}")
        bad_task = dict(env, SLURM_ARRAY_TASK_ID="7", SLURM_ARRAY_TASK_COUNT="3",
                        SLURM_ARRAY_TASK_MIN="0")
        p = run([sim, "generate", *request, "--out", os.path.join(work, "bad")], bad_task,
                expect=2)
        check("SLURM_ARRAY_TASK_ID=7" in p.stderr, f"bad array task not named: {p.stderr}")
        run([sim, "generate", *request, "--out", os.path.join(work, "bad"), "--shard", "3/3"],
            env, expect=2)
        run(["bash", os.path.join(cluster, "submit_generation.sh"), "2", *request, "--out",
             os.path.join(work, "bad"), "--shard", "0/2"], slurm_env, expect=2)
        check(not os.path.exists(os.path.join(work, "bad")), "a refused request left a folder")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if failures:
        print(f"{len(failures)} failure(s)", file=sys.stderr)
        return 1
    print("cluster scripts: one process, 2 local shards and a 3-task Slurm array agree")
    return 0


if __name__ == "__main__":
    sys.exit(main())
