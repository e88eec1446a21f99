#!/usr/bin/env python3
"""spill-sim run --vtk writes ParaView files that read back as the run's state.

Usage: vtk_output_test.py SPILL_SIM SOURCE_DIR [--infer SPILL_INFER]

Runs a short river_small (oil leaking from t = 0, 0.5 s, six frames) with --vtk and --ply, then
checks with a reader of its own (Python standard library only):
  - every .vtp is well-formed VTK XML PolyData, little-endian, UInt32 headers, one vertex cell per
    point, each binary array's byte-count header equal to its payload;
  - vtk/fluid.pvd lists every frame file on disk exactly once, named as the frame numbers, with
    strictly increasing times equal to stats.json's frames' t;
  - each frame has exactly the arrays velocity, density, pressure, oil_fraction, type and active,
    and every particle slot of the run (metadata.json's fluid_particles), in identity order;
  - the active points equal the PLY frames (written from the same state by the PLY writer):
    position, velocity, type, pressure and oil fraction, bit for bit; they lie inside the domain;
  - with h5py installed, every array equals trajectory.h5's.
Then it shows the checks are strict: a frame without an array, a collection without a frame and
a truncated array must each be rejected. With --infer, spill-infer predict --vtk and rollout --vtk
(a committed DPI-Nets checkpoint on river_small) must write the same files without density and
pressure, which a learned frame does not compute; predict's active counts equal its stats.json's.
"""

import base64
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

FLUID_ARRAYS = {
    "velocity": ("Float32", 3),
    "density": ("Float32", 1),
    "pressure": ("Float32", 1),
    "oil_fraction": ("Float32", 1),
    "type": ("Int32", 1),
    "active": ("UInt8", 1),
}
# A learned simulator's frames (spill-infer predict and rollout) have no density or pressure.
LEARNED_ARRAYS = {k: v for k, v in FLUID_ARRAYS.items() if k not in ("density", "pressure")}
STRUCT_CODE = {"Float32": "f", "Float64": "d", "Int32": "i", "UInt8": "B", "UInt32": "I"}
FRAME_FILE = re.compile(r"^fluid_(\d{5})\.vtp$")


class CheckFailed(Exception):
    pass


def require(condition, message):
    if not condition:
        raise CheckFailed(message)


def decode_array(element, where):
    """Values of an inline binary DataArray: base64 of a UInt32 byte count, then the data."""
    vtk_type = element.get("type")
    require(vtk_type in STRUCT_CODE, f"{where}: unknown DataArray type {vtk_type}")
    require(element.get("format") == "binary", f"{where}: format {element.get('format')}")
    text = "".join((element.text or "").split())
    try:
        raw = base64.b64decode(text, validate=True)
    except ValueError as e:
        raise CheckFailed(f"{where}: bad base64 ({e})")
    require(len(raw) >= 4, f"{where}: no byte-count header")
    (count,) = struct.unpack("<I", raw[:4])
    require(count == len(raw) - 4,
            f"{where}: header says {count} bytes, payload has {len(raw) - 4}")
    code = STRUCT_CODE[vtk_type]
    size = struct.calcsize(code)
    require(count % size == 0, f"{where}: {count} bytes is not a whole number of {vtk_type}")
    return list(struct.unpack(f"<{count // size}{code}", raw[4:]))


def parse_vtk_xml(path, kind):
    """The root of a VTK XML file of type `kind`, or CheckFailed naming the file."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        raise CheckFailed(f"{path}: not well-formed XML ({e})")
    require(root.tag == "VTKFile" and root.get("type") == kind, f"{path}: not {kind}")
    return root


def read_vtp(path):
    """{"n": points, "points": [x, y, z, ...], "arrays": {name: (type, components, values)}}."""
    root = parse_vtk_xml(path, "PolyData")
    require(root.get("byte_order") == "LittleEndian", f"{path}: byte_order")
    require(root.get("header_type") == "UInt32", f"{path}: header_type")
    pieces = root.findall("./PolyData/Piece")
    require(len(pieces) == 1, f"{path}: {len(pieces)} pieces")
    piece = pieces[0]
    n = int(piece.get("NumberOfPoints"))
    require(int(piece.get("NumberOfVerts")) == n, f"{path}: NumberOfVerts != NumberOfPoints")
    for cells in ("NumberOfLines", "NumberOfStrips", "NumberOfPolys"):
        require(int(piece.get(cells, "0")) == 0, f"{path}: {cells}")

    point_arrays = piece.findall("./Points/DataArray")
    require(len(point_arrays) == 1, f"{path}: Points has {len(point_arrays)} arrays")
    require(point_arrays[0].get("type") == "Float32", f"{path}: Points are not Float32")
    require(point_arrays[0].get("NumberOfComponents") == "3", f"{path}: Points are not x3")
    points = decode_array(point_arrays[0], f"{path}: Points")
    require(len(points) == 3 * n, f"{path}: {len(points)} coordinates for {n} points")

    verts = {a.get("Name"): a for a in piece.findall("./Verts/DataArray")}
    require(set(verts) == {"connectivity", "offsets"}, f"{path}: Verts arrays {sorted(verts)}")
    require(decode_array(verts["connectivity"], f"{path}: connectivity") == list(range(n)),
            f"{path}: connectivity is not one vertex per point")
    require(decode_array(verts["offsets"], f"{path}: offsets") == list(range(1, n + 1)),
            f"{path}: offsets are not one vertex per cell")

    arrays = {}
    for a in piece.findall("./PointData/DataArray"):
        name = a.get("Name")
        require(name not in arrays, f"{path}: array {name} twice")
        components = int(a.get("NumberOfComponents", "1"))
        values = decode_array(a, f"{path}: {name}")
        require(len(values) == components * n,
                f"{path}: {name} has {len(values)} values for {n} points x {components}")
        arrays[name] = (a.get("type"), components, values)
    return {"n": n, "points": points, "arrays": arrays}


def read_pvd(path):
    """[(time, file)] in the collection's order."""
    root = parse_vtk_xml(path, "Collection")
    out = []
    for d in root.findall("./Collection/DataSet"):
        require(d.get("part") == "0", f"{path}: DataSet part {d.get('part')}")
        out.append((float(d.get("timestep")), d.get("file")))
    return out


def read_ply(path):
    """Rows (x, y, z, vx, vy, vz, type, pressure, oil_fraction) of a binary PLY frame."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    require("format binary_little_endian 1.0" in header, f"{path}: PLY format")
    n = int(re.search(r"element vertex (\d+)", header).group(1))
    record = struct.Struct("<6fiff")
    require(len(data) - end == n * record.size, f"{path}: PLY size")
    return [record.unpack_from(data, end + i * record.size) for i in range(n)]


def read_series(vtk, arrays_expected, times, particles, boundary_particles, first_frame=0):
    """Checks a vtk/ folder and returns its frames, [(time, file, frame)] in time order.

    The folder holds boundary.vtp, fluid.pvd and fluid_NNNNN.vtp files and nothing else; the
    collection lists every frame file once, numbered from first_frame on, at `times`; every frame
    has `particles` points and exactly the arrays of `arrays_expected` ({name: (type, components)}).
    """
    on_disk = sorted(os.listdir(vtk))
    frame_files = [name for name in on_disk if FRAME_FILE.match(name)]
    strays = set(on_disk) - set(frame_files) - {"boundary.vtp", "fluid.pvd"}
    require(not strays, f"{vtk}: unexpected files {sorted(strays)}")
    require("boundary.vtp" in on_disk, f"{vtk}: no boundary.vtp")
    require("fluid.pvd" in on_disk, f"{vtk}: no fluid.pvd")

    boundary = read_vtp(os.path.join(vtk, "boundary.vtp"))
    require(boundary["n"] == boundary_particles,
            f"boundary.vtp: {boundary['n']} points, metadata.json {boundary_particles}")
    require(set(boundary["arrays"]) == {"type"},
            f"boundary.vtp: arrays {sorted(boundary['arrays'])}")
    require(boundary["arrays"]["type"][:2] == ("Int32", 1), "boundary.vtp: type is not Int32")
    require(set(boundary["arrays"]["type"][2]) == {2}, "boundary.vtp: type is not 2 everywhere")

    collection = read_pvd(os.path.join(vtk, "fluid.pvd"))
    listed = [file for _, file in collection]
    require(len(listed) == len(set(listed)), f"fluid.pvd lists a file twice: {listed}")
    require(sorted(listed) == frame_files,
            f"fluid.pvd lists {sorted(listed)}, the folder has {frame_files}")
    listed_times = [t for t, _ in collection]
    require(all(b > a for a, b in zip(listed_times, listed_times[1:])),
            f"fluid.pvd: times not increasing {listed_times}")
    require(len(listed_times) == len(times),
            f"fluid.pvd has {len(listed_times)} frames, expected {len(times)}")
    frames = []
    for k, (t, file) in enumerate(collection):
        require(abs(t - times[k]) <= 1e-9, f"{file}: t = {t}, expected {times[k]}")
        require(int(FRAME_FILE.match(file).group(1)) == first_frame + k,
                f"frame {first_frame + k} is in {file}")
        frame = read_vtp(os.path.join(vtk, file))
        require(frame["n"] == particles,
                f"{file}: {frame['n']} points, the run has {particles} particle slots")
        arrays = frame["arrays"]
        require(set(arrays) == set(arrays_expected),
                f"{file}: arrays {sorted(arrays)}, expected {sorted(arrays_expected)}")
        for name, kind in arrays_expected.items():
            require(arrays[name][:2] == kind,
                    f"{file}: {name} is {arrays[name][:2]}, expected {kind}")
        active, oil, types = arrays["active"][2], arrays["oil_fraction"][2], arrays["type"][2]
        require(set(active) <= {0, 1}, f"{file}: active is not 0/1")
        for i in range(particles):
            if active[i]:
                require(0 <= oil[i] <= 1, f"{file}: particle {i} oil fraction {oil[i]}")
                require(types[i] in (0, 1), f"{file}: particle {i} type {types[i]}")
        frames.append((t, file, frame))
    return frames


def check_run(run):
    """Every check on spill-sim run's folder; raises CheckFailed naming the first that fails."""
    with open(os.path.join(run, "metadata.json")) as f:
        metadata = json.load(f)
    with open(os.path.join(run, "stats.json")) as f:
        stats = json.load(f)
    particles = metadata["fluid_particles"]
    bounds = metadata["bounds"]  # [[xmin, xmax], [ymin, ymax], [zmin, zmax]]
    frames = read_series(os.path.join(run, "vtk"), FLUID_ARRAYS,
                         [frame["t"] for frame in stats["frames"]], particles,
                         metadata["boundary_particles"])

    previous = None
    oil_seen = 0
    for k, (t, file, frame) in enumerate(frames):
        points, arrays = frame["points"], frame["arrays"]
        velocity, pressure = arrays["velocity"][2], arrays["pressure"][2]
        oil, density = arrays["oil_fraction"][2], arrays["density"][2]
        types, active = arrays["type"][2], arrays["active"][2]
        ids = [i for i in range(particles) if active[i]]
        for i in ids:
            p = points[3 * i:3 * i + 3]
            require(all(bounds[d][0] <= p[d] <= bounds[d][1] for d in range(3)),
                    f"{file}: particle {i} at {p} is outside the domain {bounds}")
            require(density[i] > 0, f"{file}: particle {i} density {density[i]}")
        oil_seen = max(oil_seen, sum(1 for i in ids if oil[i] >= 0.5))

        # The PLY frame holds the active particles' state (in the solver's order).
        ply = read_ply(os.path.join(run, "ply", file.replace(".vtp", ".ply")))
        require(len(ply) == len(ids), f"{file}: {len(ids)} active points, the PLY {len(ply)}")
        mine = sorted(tuple(points[3 * i:3 * i + 3]) + tuple(velocity[3 * i:3 * i + 3]) +
                      (types[i], pressure[i], oil[i]) for i in ids)
        require(mine == sorted(ply), f"{file}: the active points differ from the PLY frame's")

        # Identity order: a particle active in two frames in a row moves about v * dt, not across
        # the reach (a shuffle would); only a few (retired and released again) may jump.
        if previous is not None:
            dt = t - frames[k - 1][0]
            p_points, p_velocity, p_active = previous
            both = [i for i in ids if p_active[i]]
            jumps = 0
            for i in both:
                move = sum((points[3 * i + d] - p_points[3 * i + d]) ** 2 for d in range(3)) ** 0.5
                speed = max(sum(v[3 * i + d] ** 2 for d in range(3)) ** 0.5
                            for v in (velocity, p_velocity))
                jumps += move > 2 * speed * dt + 0.05
            require(both and jumps <= 0.002 * len(both),
                    f"{file}: {jumps} of {len(both)} particles jumped since the previous frame")
        previous = (points, velocity, active)

    last_active, final = sum(previous[2]), stats["summary"]["fluid_particles"]
    require(last_active == final, f"last frame: {last_active} active points, stats.json {final}")
    require(oil_seen > 0, "no frame has oil: the oil fraction array is not exercised")
    return len(frames)


def compare_with_trajectory(run):
    """With h5py: every frame's arrays equal trajectory.h5's (float32 bit for bit)."""
    try:
        import h5py  # optional: not in the standard library
    except ImportError:
        return False
    vtk = os.path.join(run, "vtk")
    collection = read_pvd(os.path.join(vtk, "fluid.pvd"))
    with h5py.File(os.path.join(run, "trajectory.h5"), "r") as h5:
        group = h5[list(h5.keys())[0]]
        for k, (t, file) in enumerate(collection):
            frame = read_vtp(os.path.join(vtk, file))
            require(abs(float(group["time"][k]) - t) <= 1e-9, f"{file}: time vs trajectory.h5")
            pairs = [(frame["points"], group["position"][k].reshape(-1)),
                     (frame["arrays"]["velocity"][2], group["velocity"][k].reshape(-1)),
                     (frame["arrays"]["oil_fraction"][2], group["volume_fraction"][k]),
                     (frame["arrays"]["active"][2], group["active"][k])]
            for mine, theirs in pairs:
                require([float(x) for x in mine] == [float(x) for x in theirs],
                        f"{file}: differs from trajectory.h5")
    return True


def run_command(command):
    done = subprocess.run(command, env=dict(os.environ, OMP_NUM_THREADS="1"),
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode != 0:
        print(done.stdout)
        raise CheckFailed(f"{' '.join(command)} exited {done.returncode}")


def read_json(path):
    with open(path) as f:
        return json.load(f)


def check_predict(spill_infer, checkpoint, scene, work):
    """spill-infer predict --vtk: the run folder's frames, active counts as in stats.json."""
    out = os.path.join(work, "predicted")
    run_command([spill_infer, "predict", "--checkpoint", checkpoint, "--scene", scene, "--out", out,
                 "--threads", "1", "--vtk", "--set", "/end_time=0.3", "--set", "/leaks/0/start=0"])
    metadata = read_json(os.path.join(out, "metadata.json"))
    stats = read_json(os.path.join(out, "stats.json"))
    frames = read_series(os.path.join(out, "vtk"), LEARNED_ARRAYS,
                         [frame["t"] for frame in stats["frames"]], metadata["fluid_particles"],
                         metadata["boundary_particles"])
    for (_, file, frame), recorded in zip(frames, stats["frames"]):
        active = sum(frame["arrays"]["active"][2])
        require(active == recorded["active"],
                f"predict {file}: {active} active points, stats.json {recorded['active']}")
    return len(frames)


def check_rollout(spill_sim, spill_infer, checkpoint, scene, work):
    """spill-infer rollout --vtk: the predicted frames, numbered and timed as the recording's."""
    data, out = os.path.join(work, "data"), os.path.join(work, "rollout")
    run_command([spill_sim, "generate", "--scene", scene, "--trajectories", "1", "--out", data,
                 "--split", "0/0/1", "--frames", "8", "--warm-up", "0", "--threads", "1",
                 "--set", "/leaks/0/start=0"])
    first = 5
    run_command([spill_infer, "rollout", "--checkpoint", checkpoint, "--data", data, "--split",
                 "test", "--trajectory", "0", "--from", str(first), "--out", out, "--threads", "1",
                 "--vtk"])
    metadata = read_json(os.path.join(data, "metadata.json"))
    frames = read_json(os.path.join(out, "metadata.json"))["rollout"]["frames"] + 1
    times = [(first + k) * metadata["frame_dt"] for k in range(frames)]
    return len(read_series(os.path.join(out, "vtk"), LEARNED_ARRAYS, times,
                           metadata["fluid_particles"], metadata["boundary_particles"], first))


def expect_rejected(run, what, mutate):
    broken = run + "_broken"
    shutil.rmtree(broken, ignore_errors=True)
    shutil.copytree(run, broken)
    mutate(os.path.join(broken, "vtk"))
    try:
        check_run(broken)
    except CheckFailed as e:
        print(f"  rejected as expected ({what}): {e}")
        return
    finally:
        shutil.rmtree(broken, ignore_errors=True)
    raise CheckFailed(f"the checks accepted a run with {what}")


def drop_array(vtk):
    path = os.path.join(vtk, "fluid_00002.vtp")
    tree = ET.parse(path)
    point_data = tree.getroot().find("./PolyData/Piece/PointData")
    point_data.remove([a for a in point_data if a.get("Name") == "density"][0])
    tree.write(path, xml_declaration=True)


def drop_frame(vtk):
    path = os.path.join(vtk, "fluid.pvd")
    tree = ET.parse(path)
    collection = tree.getroot().find("./Collection")
    collection.remove(collection.findall("DataSet")[3])
    tree.write(path, xml_declaration=True)


def truncate_array(vtk):
    path = os.path.join(vtk, "fluid_00001.vtp")
    tree = ET.parse(path)
    points = tree.getroot().find("./PolyData/Piece/Points/DataArray")
    raw = base64.b64decode("".join(points.text.split()))
    points.text = base64.b64encode(raw[:-12]).decode()  # one point short, header unchanged
    tree.write(path, xml_declaration=True)


def main():
    args = sys.argv[1:]
    if len(args) not in (2, 4) or (len(args) == 4 and args[2] != "--infer"):
        sys.exit(__doc__)
    spill_sim, source = args[0], args[1]
    spill_infer = args[3] if len(args) == 4 else None
    scene = os.path.join(source, "configs", "scenes", "river_small.json")
    work = tempfile.mkdtemp(prefix="vtk_output_test_")
    try:
        run = os.path.join(work, "run")
        start = time.monotonic()
        run_command([spill_sim, "run", "--scene", scene, "--out", run, "--threads", "1", "--vtk",
                     "--ply", "--set", "/end_time=0.5", "--set", "/output/frame_dt=0.1",
                     "--set", "/leaks/0/start=0"])
        print(f"spill-sim run took {time.monotonic() - start:.2f} s")
        frames = check_run(run)
        print(f"{frames} frames and the boundary read back as the run's state")
        if compare_with_trajectory(run):
            print("the frames equal trajectory.h5's")
        else:
            print("h5py not installed: trajectory.h5 not compared (the PLY frames were)")
        expect_rejected(run, "a frame without its density array", drop_array)
        expect_rejected(run, "a collection without frame 3", drop_frame)
        expect_rejected(run, "a truncated Points array", truncate_array)
        if spill_infer:
            checkpoint = os.path.join(source, "docs", "results", "baselines", "dpi.pt")
            start = time.monotonic()
            frames = check_predict(spill_infer, checkpoint, scene, work)
            print(f"spill-infer predict --vtk: {frames} frames without density and pressure")
            frames = check_rollout(spill_sim, spill_infer, checkpoint, scene, work)
            print(f"spill-infer rollout --vtk: {frames} frames; spill-infer took "
                  f"{time.monotonic() - start:.2f} s")
    except CheckFailed as e:
        sys.exit(f"FAILED: {e}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("OK")


if __name__ == "__main__":
    main()
