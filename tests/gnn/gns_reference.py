#!/usr/bin/env python3
"""Plain-PyTorch reference of the GNS network, for tests/gnn/gns_reference_test.cpp.

What it is: the GNS of docs/models.md ("GNS" section; Sanchez-Gonzalez et al. 2020,
"Learning to Simulate Complex Physics with Graph Networks") written the plain, readable
PyTorch way, independently of the C++ code and without its optimisations:

  encoder    node: MLP([node_features, type_embedding]) + LayerNorm
             edge: MLP(edge_features) + LayerNorm
  processor  `layers` interaction-network steps, each with its own weights:
               e_ij' = MLP([e_ij, v_i, v_j]) + LayerNorm      (i receiver, j sender)
               a_i   = sum over edges into i of e_ij'         (index_add_)
               v_i'  = MLP([v_i, a_i]) + LayerNorm
               e_ij <- e_ij + e_ij',  v_i <- v_i + v_i'       (residuals)
  decoder    MLP(v) to 4 outputs (acceleration, oil fraction change), no LayerNorm
  every MLP  Linear, ReLU, ..., Linear with `mlp_hidden_layers` hidden layers of width `latent`

The C++ model splits the first Linear of each processor MLP into per-input pieces (the edge
MLP's into e_ij, receiver and sender parts; the node MLP's into v_i and aggregate parts). Here
each is one Linear over the concatenated input; `load_parameters` joins the C++ pieces into it
explicitly and fails if any C++ parameter is left unused or any reference parameter unset.

It computes in float64 so that the difference to the C++ float32 result is the C++ error alone.

Usage: python3 gns_reference.py IN OUT
  IN   torch::pickle_save'd dict: "config" (the model's JSON), "parameters" (name -> tensor, the
       C++ named_parameters), "inputs" (node_features, node_type, edge_index, edge_features)
  OUT  torch.save'd [nodes, 4] float64 tensor: the network's output for every node
Needs Debian's python3-torch (PyTorch 1.13, CPU).
"""

import json
import sys

import torch
from torch import nn


def mlp(in_size, latent, out_size, hidden_layers, layer_norm):
    """Linear(in, L) ReLU [Linear(L, L) ReLU] * (H - 1) Linear(L, out) [LayerNorm(out)]."""
    layers = [nn.Linear(in_size, latent), nn.ReLU()]
    for _ in range(hidden_layers - 1):
        layers += [nn.Linear(latent, latent), nn.ReLU()]
    layers.append(nn.Linear(latent, out_size))
    if layer_norm:
        layers.append(nn.LayerNorm(out_size))
    return nn.Sequential(*layers)


class InteractionNetwork(nn.Module):
    """One processor step with its own weights."""

    def __init__(self, latent, hidden_layers):
        super().__init__()
        self.edge_mlp = mlp(3 * latent, latent, latent, hidden_layers, True)
        self.node_mlp = mlp(2 * latent, latent, latent, hidden_layers, True)

    def forward(self, v, e, senders, receivers):
        edge_in = torch.cat([e, v[receivers], v[senders]], dim=1)
        e_update = self.edge_mlp(edge_in)
        aggregated = torch.zeros_like(v).index_add_(0, receivers, e_update)
        v_update = self.node_mlp(torch.cat([v, aggregated], dim=1))
        return v + v_update, e + e_update


class Gns(nn.Module):
    def __init__(self, node_features, edge_features, node_types, config):
        super().__init__()
        latent, hidden = config["latent"], config["mlp_hidden_layers"]
        self.type_embedding = nn.Embedding(node_types, config["type_embedding"])
        self.node_encoder = mlp(node_features + config["type_embedding"], latent, latent, hidden,
                                True)
        self.edge_encoder = mlp(edge_features, latent, latent, hidden, True)
        self.processor = nn.ModuleList(
            [InteractionNetwork(latent, hidden) for _ in range(config["layers"])])
        self.decoder = mlp(latent, latent, 4, hidden, False)

    def forward(self, node_features, node_type, edge_index, edge_features):
        senders, receivers = edge_index[0], edge_index[1]
        v = self.node_encoder(torch.cat([node_features, self.type_embedding(node_type)], dim=1))
        e = self.edge_encoder(edge_features)
        for step in self.processor:
            v, e = step(v, e, senders, receivers)
        return self.decoder(v)


def linears(sequential):
    return [m for m in sequential if isinstance(m, nn.Linear)]


def load_parameters(model, ours, config):
    """Copies the C++ parameters (by name) into the reference modules, joining split layers."""
    used = set()

    def take(name):
        if name not in ours:
            raise KeyError(f"the C++ model has no parameter {name!r}")
        used.add(name)
        return ours[name].to(torch.float64)

    def set_mlp(sequential, prefix, first_weight=None):
        for k, linear in enumerate(linears(sequential)):
            weight = take(f"{prefix}.linear{k}.weight")
            if k == 0 and first_weight is not None:
                weight = first_weight(weight)
            linear.weight.copy_(weight)
            linear.bias.copy_(take(f"{prefix}.linear{k}.bias"))
        norm = sequential[-1]
        if isinstance(norm, nn.LayerNorm):
            norm.weight.copy_(take(f"{prefix}.norm.weight"))
            norm.bias.copy_(take(f"{prefix}.norm.bias"))

    latent = config["latent"]
    with torch.no_grad():
        model.type_embedding.weight.copy_(take("type_embedding.weight"))
        set_mlp(model.node_encoder, "node_encoder")
        set_mlp(model.edge_encoder, "edge_encoder")
        for k, step in enumerate(model.processor):
            # C++: first edge layer = W_e e_ij + (W_rs v)[:L] at the receiver + (W_rs v)[L:] at
            # the sender, so W over [e_ij, v_i, v_j] is [W_e | W_rs[:L] | W_rs[L:]].
            receiver_sender = take(f"edge_receiver_sender{k}.weight")
            assert receiver_sender.shape == (2 * latent, latent)
            set_mlp(step.edge_mlp, f"edge_mlp{k}",
                    lambda w: torch.cat([w, receiver_sender[:latent], receiver_sender[latent:]],
                                        dim=1))
            # C++: first node layer = W_v v_i + W_a a_i (+ bias), so W over [v_i, a_i] = [W_v | W_a].
            aggregate = take(f"node_aggregate{k}.weight")
            set_mlp(step.node_mlp, f"node_mlp{k}", lambda w: torch.cat([w, aggregate], dim=1))
        set_mlp(model.decoder, "decoder")
    unused = sorted(set(ours) - used)
    if unused:
        raise KeyError(f"C++ parameters the reference does not know: {unused}")


def main(argv):
    if len(argv) != 3:
        sys.exit(f"usage: {argv[0]} IN OUT")
    data = torch.load(argv[1])
    config = json.loads(data["config"])
    if config["model"] != "gns":
        sys.exit(f"not a GNS config: {config['model']}")
    ours = data["parameters"]
    inputs = data["inputs"]
    node_features = inputs["node_features"].to(torch.float64)
    edge_features = inputs["edge_features"].to(torch.float64)
    node_types = ours["type_embedding.weight"].shape[0]
    model = Gns(node_features.shape[1], edge_features.shape[1], node_types, config)
    model = model.to(torch.float64)
    load_parameters(model, ours, config)
    model.eval()
    with torch.no_grad():
        output = model(node_features, inputs["node_type"], inputs["edge_index"], edge_features)
    # The bare tensor: LibTorch 1.13's unpickler (torch::pickle_load) lacks the SETITEM opcode
    # that Python's pickle writes for a dict of one entry.
    torch.save(output, argv[2], _use_new_zipfile_serialization=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
