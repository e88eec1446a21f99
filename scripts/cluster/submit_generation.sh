#!/usr/bin/env bash
# Queues a dataset generation on a Slurm cluster: an array of SHARDS tasks (generate_shard.sbatch,
# one trajectory share each) and an assembling job that runs when all of them succeeded.
#   scripts/cluster/submit_generation.sh SHARDS --scene S --trajectories N --out DIR [generate options]
# DIR must be on a file system every node sees. Extra sbatch options (partition, account, time)
# go in SBATCH_ARGS, e.g. SBATCH_ARGS="--partition=short --time=01:00:00". Prints the two job ids.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
if [ $# -lt 2 ] || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: $0 SHARDS --scene S --trajectories N --out DIR [spill-sim generate options]" >&2
  exit 2
fi
shards=$1
shift
out=""
args=("$@")
for ((k = 0; k < ${#args[@]}; ++k)); do
  case "${args[k]}" in
    --out) out="${args[k + 1]:-}" ;;
    --out=*) out="${args[k]#--out=}" ;;
    --shard | --shard=*)
      echo "$0: the array gives each task its shard; leave --shard out" >&2
      exit 2
      ;;
  esac
done
if [ -z "$out" ]; then
  echo "$0: --out DIR is required" >&2
  exit 2
fi
# shellcheck disable=SC2086  # SBATCH_ARGS holds several options
array=$(sbatch --parsable ${SBATCH_ARGS:-} --array="0-$((shards - 1))" \
  "$here/generate_shard.sbatch" "$@")
array=${array%%;*}  # --parsable prints "id" or "id;cluster"
# shellcheck disable=SC2086
assemble=$(sbatch --parsable ${SBATCH_ARGS:-} --dependency="afterok:$array" \
  "$here/assemble.sbatch" "$out")
echo "shards: job $array (array 0-$((shards - 1))); assemble: job ${assemble%%;*}"
