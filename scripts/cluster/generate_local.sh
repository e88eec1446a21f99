#!/usr/bin/env bash
# The same sharded generation on one big machine, without a scheduler: SHARDS processes side by
# side (xargs -P), each `spill-sim generate --shard I/SHARDS` of one thread, writing into the same
# dataset folder; the last to finish assembles the dataset. Rerunning resumes what a crash or
# Ctrl-C left.
#   scripts/cluster/generate_local.sh SHARDS --scene S --trajectories N --out DIR [generate options]
# SPILL_SIM names the executable (default: spill-sim on PATH).
set -euo pipefail
if [ $# -lt 2 ] || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: $0 SHARDS --scene S --trajectories N --out DIR [spill-sim generate options]" >&2
  exit 2
fi
shards=$1
shift
sim="${SPILL_SIM:-spill-sim}"
# xargs exits 123 when any shard failed; each shard's own message is on stderr above.
seq 0 $((shards - 1)) |
  xargs -P "$shards" -I{} "$sim" generate "$@" --shard "{}/$shards"
