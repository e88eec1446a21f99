#!/usr/bin/env python3
"""Python PyTorch reference implementation of one GNS training step.

Purpose: reference for the claim that the C++ GNS trains no slower than the
same model in Python PyTorch.  This script builds the same synthetic particle
graph as the C++ LibTorch benchmark and times the same encode-process-decode
GNS (Sanchez-Gonzalez et al. 2020, "Learning to Simulate Complex Physics with
Graph Networks"), written the plain, idiomatic PyTorch way (torch.cat,
index_select, index_add_).  It is a baseline, deliberately not tuned.

Measurements (median wall seconds over --repeat runs, after --warmup runs):
  forward_s     forward pass only, under torch.no_grad()
  train_step_s  forward + MSE loss + backward + Adam(lr=1e-4) step + zero_grad

Prints a single JSON object on stdout.

Run with the Debian system interpreter (python3-torch, CPU build), e.g.:
  /usr/bin/python3 tests/bench/gns_pytorch_reference.py --threads 2
"""

import argparse
import json
import os
import platform
import resource
import statistics
import sys
import time

LATTICE_SPACING = 0.05  # m, must match the C++ benchmark
NUM_NODE_TYPES = 3
TYPE_EMBEDDING_SIZE = 16
NUM_PREV_VELOCITIES = 5
DIM = 3
NUM_MATERIAL_FEATURES = 2
NUM_BOUND_FEATURES = 6  # distance to the 6 faces of the domain
SEED = 0


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--particles", type=int, default=10000,
                   help="requested particle count; the lattice has round(N**(1/3))**3")
    p.add_argument("--radius", type=float, default=0.1,
                   help="connectivity radius in m (strict |x_i - x_j| < R)")
    p.add_argument("--latent", type=int, default=128, help="latent size L")
    p.add_argument("--layers", type=int, default=10,
                   help="message-passing steps K (separate weights)")
    p.add_argument("--mlp-hidden-layers", type=int, default=2,
                   help="hidden layers H of width L in every MLP")
    p.add_argument("--threads", type=int, default=2, help="torch.set_num_threads")
    p.add_argument("--repeat", type=int, default=5, help="timed runs")
    p.add_argument("--warmup", type=int, default=1, help="untimed runs first")
    a = p.parse_args(argv)
    if a.particles < 1 or a.latent < 1 or a.layers < 1 or a.mlp_hidden_layers < 1:
        p.error("--particles, --latent, --layers, --mlp-hidden-layers must be >= 1")
    if a.threads < 1 or a.repeat < 1 or a.warmup < 0 or a.radius <= 0:
        p.error("--threads/--repeat >= 1, --warmup >= 0, --radius > 0")
    return a


ARGS = parse_args()
# Debian's torch calls the system BLAS (OpenBLAS via libblas.so.3), whose own
# thread pool is not governed by torch.set_num_threads; pin it to the same
# count before torch (and thus OpenBLAS) is loaded, unless the caller set it.
os.environ.setdefault("OPENBLAS_NUM_THREADS", str(ARGS.threads))

import numpy as np  # noqa: E402
import torch  # noqa: E402
from torch import nn  # noqa: E402


# --------------------------------------------------------------------------
# Synthetic graph
# --------------------------------------------------------------------------

def lattice_positions(n_requested):
    """Cubic lattice, spacing 0.05 m, side s = round(N**(1/3)); index i*s*s + j*s + k."""
    s = int(round(n_requested ** (1.0 / 3.0)))
    s = max(s, 1)
    r = np.arange(s, dtype=np.float64)
    i, j, k = np.meshgrid(r, r, r, indexing="ij")
    pos = np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1) * LATTICE_SPACING
    return pos


def radius_edges(pos, radius):
    """All ordered pairs with |x_i - x_j| < radius, both directions, sorted by receiver.

    Returns int64 array [2, E]: row 0 = sender (src), row 1 = receiver (dst).
    """
    # All pairs closer than the radius, by distances in row blocks (no SciPy on a bare Debian;
    # 10,000 particles take a few tenths of a second).
    points = torch.from_numpy(np.asarray(pos, dtype=np.float64))
    src_parts, dst_parts = [], []
    for start in range(0, len(points), 2048):
        block = torch.cdist(points[start:start + 2048], points)
        i, j = torch.nonzero(block < radius - 1e-9, as_tuple=True)
        i = i + start
        keep = i != j
        src_parts.append(j[keep].numpy())
        dst_parts.append(i[keep].numpy())
    if not src_parts or sum(len(p) for p in src_parts) == 0:
        return np.zeros((2, 0), dtype=np.int64)
    src = np.concatenate(src_parts)
    dst = np.concatenate(dst_parts)
    order = np.lexsort((src, dst))  # primary key receiver, then sender
    return np.stack([src[order], dst[order]]).astype(np.int64)


# --------------------------------------------------------------------------
# Model
# --------------------------------------------------------------------------

def mlp(in_size, out_size, latent, hidden_layers, layer_norm):
    """Linear(in,L) ReLU [Linear(L,L) ReLU]*(H-1) Linear(L,out) [LayerNorm(out)]."""
    mods = [nn.Linear(in_size, latent), nn.ReLU()]
    for _ in range(hidden_layers - 1):
        mods += [nn.Linear(latent, latent), nn.ReLU()]
    mods.append(nn.Linear(latent, out_size))
    if layer_norm:
        mods.append(nn.LayerNorm(out_size))
    return nn.Sequential(*mods)


class InteractionNetwork(nn.Module):
    def __init__(self, latent, hidden_layers):
        super().__init__()
        self.edge_mlp = mlp(3 * latent, latent, latent, hidden_layers, True)
        self.node_mlp = mlp(2 * latent, latent, latent, hidden_layers, True)

    def forward(self, v, e, senders, receivers):
        v_dst = v.index_select(0, receivers)
        v_src = v.index_select(0, senders)
        e_new = self.edge_mlp(torch.cat([e, v_dst, v_src], dim=-1))
        agg = torch.zeros_like(v).index_add_(0, receivers, e_new)
        v_new = self.node_mlp(torch.cat([v, agg], dim=-1))
        return v + v_new, e + e_new


class GNS(nn.Module):
    def __init__(self, node_in, edge_in, latent, layers, hidden_layers, out_size, radius):
        super().__init__()
        self.radius = radius
        self.type_embedding = nn.Embedding(NUM_NODE_TYPES, TYPE_EMBEDDING_SIZE)
        self.node_encoder = mlp(node_in, latent, latent, hidden_layers, True)
        self.edge_encoder = mlp(edge_in, latent, latent, hidden_layers, True)
        self.processor = nn.ModuleList(
            [InteractionNetwork(latent, hidden_layers) for _ in range(layers)])
        self.decoder = mlp(latent, out_size, latent, hidden_layers, False)

    def forward(self, pos, node_type, node_feats, edge_index):
        senders, receivers = edge_index[0], edge_index[1]
        # Node inputs: [prev velocities (15), type embedding (16), material (2), bounds (6)]
        vel = node_feats[:, : NUM_PREV_VELOCITIES * DIM]
        rest = node_feats[:, NUM_PREV_VELOCITIES * DIM:]
        node_in = torch.cat([vel, self.type_embedding(node_type), rest], dim=-1)
        # Edge inputs: relative displacement / R and its norm
        rel = (pos.index_select(0, senders) - pos.index_select(0, receivers)) / self.radius
        edge_in = torch.cat([rel, rel.norm(dim=-1, keepdim=True)], dim=-1)

        v = self.node_encoder(node_in)
        e = self.edge_encoder(edge_in)
        for block in self.processor:
            v, e = block(v, e, senders, receivers)
        return self.decoder(v)


# --------------------------------------------------------------------------
# Benchmark
# --------------------------------------------------------------------------

def timed(fn, warmup, repeat):
    for _ in range(warmup):
        fn()
    runs = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        runs.append(time.perf_counter() - t0)
    return statistics.median(runs), runs


def main(args):
    torch.set_num_threads(args.threads)
    torch.manual_seed(SEED)
    rng = np.random.default_rng(SEED)

    pos_np = lattice_positions(args.particles)
    n = pos_np.shape[0]
    edge_index_np = radius_edges(pos_np, args.radius)

    n_other = NUM_PREV_VELOCITIES * DIM + NUM_MATERIAL_FEATURES + NUM_BOUND_FEATURES  # 23
    node_in_size = n_other + TYPE_EMBEDDING_SIZE  # 39
    edge_in_size = DIM + 1  # 4

    pos = torch.from_numpy(pos_np).float()
    edge_index = torch.from_numpy(edge_index_np)
    node_type = torch.zeros(n, dtype=torch.long)  # all water
    node_feats = torch.from_numpy(rng.standard_normal((n, n_other))).float()
    target = torch.from_numpy(rng.standard_normal((n, DIM))).float()

    model = GNS(node_in_size, edge_in_size, args.latent, args.layers,
                args.mlp_hidden_layers, DIM, args.radius)
    optimizer = torch.optim.Adam(model.parameters(), lr=1e-4)
    loss_fn = nn.MSELoss()

    def forward_only():
        with torch.no_grad():
            model(pos, node_type, node_feats, edge_index)

    def train_step():
        pred = model(pos, node_type, node_feats, edge_index)
        loss = loss_fn(pred, target)
        loss.backward()
        optimizer.step()
        optimizer.zero_grad()
        return loss

    model.eval()  # no dropout/batchnorm, so eval/train only differ nominally
    forward_s, forward_runs = timed(forward_only, args.warmup, args.repeat)
    model.train()
    train_step_s, train_runs = timed(train_step, args.warmup, args.repeat)

    result = {
        "framework": "pytorch",
        "torch_version": torch.__version__,
        "threads": torch.get_num_threads(),
        "particles": n,
        "edges": int(edge_index_np.shape[1]),
        "latent": args.latent,
        "layers": args.layers,
        "mlp_hidden_layers": args.mlp_hidden_layers,
        "radius": args.radius,
        "forward_s": forward_s,
        "train_step_s": train_step_s,
        "forward_runs": forward_runs,
        "train_step_runs": train_runs,
        # extra context, not part of the comparison itself
        "parameters": sum(p.numel() for p in model.parameters()),
        "warmup": args.warmup,
        "repeat": args.repeat,
        "openblas_num_threads": os.environ.get("OPENBLAS_NUM_THREADS"),
        "python_version": platform.python_version(),
        # the process's peak resident memory (Linux reports ru_maxrss in KiB)
        "peak_memory_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
    }
    json.dump(result, sys.stdout)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(ARGS))
