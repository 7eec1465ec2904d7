#!/usr/bin/env python3
"""Equal-quality comparison with Mitsuba 3 (installed outside this repository):

  MITSUBA_PYTHON=/path/to/venv/bin/python DRJIT_LIBLLVM_PATH=/path/to/libLLVM.so \\
    bench/compare_mitsuba.py [--clrender PATH] [--scene bench/scenes/cornell.pbrt] [--reps N]
        [--ref-spp N] [--ref-sampler sobol] [--target-spp N] [--target-sampler sobol]
        [--max-spp N] [--threads N] [--res N] [--maxdepth 5] [--clr-samplers "halton sobol zsobol"]
        [--mi-samplers "independent stratified multijitter ldsampler"]

Renders the pbrt Cornell box (path tracer, maxdepth 5, box filter) with clrender and with
Mitsuba 3's llvm_ad_rgb variant (the scene translated by a tiny parser of that one pbrt file into
Mitsuba's dict API: same camera, triangles, two-sided diffuse materials, one-sided area light).
The reference is a clrender render at --ref-spp with --ref-sampler (halton and sobol ignore the
seed: a sobol reference shares its first samples with the sobol sweep; "random" avoids that at
the price of a noisier reference); Mitsuba's high-spp mean is checked against it.
Each sampler is swept over powers of two of spp (each render a fresh process, renderers and
samplers interleaved, the order rotating per repetition); relRMSE = sqrt(mean over pixels and
channels of (x - ref)^2 / (ref^2 + 1e-2)), as bench/adaptive_rmse.sh. The target error is
clrender's --target-sampler at --target-spp; the time to reach it is interpolated on log-log
between the two sweep points that bracket it, from the medians of wall and of CPU time (user +
system of the process: start-up, scene, JIT compilation or kernel cache, render, output).
Prints JSON Lines and a summary table. Without an importable Mitsuba 3 it says so and exits 0.
"""
import json, math, os, shutil, statistics, struct, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))


# ---------------------------------------------------------------- pbrt file -> geometry


def tokens(text):
    out, i = [], 0
    while i < len(text):
        c = text[i]
        if c == "#":
            i = text.find("\n", i) if "\n" in text[i:] else len(text)
        elif c.isspace():
            i += 1
        elif c in "[]":
            out.append(c)
            i += 1
        elif c == '"':
            j = text.index('"', i + 1)
            out.append(text[i:j + 1])
            i = j + 1
        else:
            j = i
            while j < len(text) and not text[j].isspace() and text[j] not in '[]"#':
                j += 1
            out.append(text[i:j])
            i = j
    return out


def matmul(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(4)) for c in range(4)] for r in range(4)]


def translate(x, y, z):
    return [[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]]


def scale(x, y, z):
    return [[x, 0, 0, 0], [0, y, 0, 0], [0, 0, z, 0], [0, 0, 0, 1]]


def rotate(deg, ax, ay, az):
    n = math.sqrt(ax * ax + ay * ay + az * az)
    ax, ay, az = ax / n, ay / n, az / n
    s, c = math.sin(math.radians(deg)), math.cos(math.radians(deg))
    return [[ax * ax + (1 - ax * ax) * c, ax * ay * (1 - c) - az * s, ax * az * (1 - c) + ay * s, 0],
            [ax * ay * (1 - c) + az * s, ay * ay + (1 - ay * ay) * c, ay * az * (1 - c) - ax * s, 0],
            [ax * az * (1 - c) - ay * s, ay * az * (1 - c) + ax * s, az * az + (1 - az * az) * c, 0],
            [0, 0, 0, 1]]


def parse_pbrt(path):
    """Camera, triangle meshes (world-space points, faces, material rgb, emitted rgb or None)."""
    toks = tokens(open(path).read())
    pos = [0]

    def fail(msg):
        sys.exit("compare_mitsuba: %s: %s (only the constructs of bench/scenes/cornell.pbrt "
                 "are translated)" % (path, msg))

    def nums(n):
        v = [float(t) for t in toks[pos[0]:pos[0] + n]]
        pos[0] += n
        return v

    def params():
        p = {}
        while pos[0] < len(toks) and toks[pos[0]].startswith('"') and " " in toks[pos[0]]:
            key = toks[pos[0]].strip('"').split()[1]
            pos[0] += 1
            vals = []
            if toks[pos[0]] == "[":
                pos[0] += 1
                while toks[pos[0]] != "]":
                    vals.append(toks[pos[0]])
                    pos[0] += 1
            else:
                vals.append(toks[pos[0]])
            pos[0] += 1
            p[key] = vals
        return p

    def kd(p):
        return [float(v) for v in p.get("Kd", ["0.5", "0.5", "0.5"])]

    ctm, stack, named, material, light = scale(1, 1, 1), [], {}, [0.5] * 3, None
    cam, meshes = {}, []
    while pos[0] < len(toks):
        t = toks[pos[0]]
        pos[0] += 1
        if t == "LookAt":
            cam["lookat"] = nums(9)
        elif t == "Camera":
            if toks[pos[0]] != '"perspective"':
                fail("camera %s" % toks[pos[0]])
            pos[0] += 1
            cam["fov"] = float(params().get("fov", ["90"])[0])
        elif t in ("WorldBegin", "WorldEnd"):
            ctm = scale(1, 1, 1)
        elif t == "AttributeBegin":
            stack.append((ctm, material, light))
        elif t == "AttributeEnd":
            ctm, material, light = stack.pop()
        elif t == "Translate":
            ctm = matmul(ctm, translate(*nums(3)))
        elif t == "Scale":
            ctm = matmul(ctm, scale(*nums(3)))
        elif t == "Rotate":
            ctm = matmul(ctm, rotate(*nums(4)))
        elif t == "AreaLightSource":
            pos[0] += 1
            light = [float(v) for v in params()["L"]]
        elif t == "Material":
            pos[0] += 1
            material = kd(params())
        elif t == "MakeNamedMaterial":
            name = toks[pos[0]].strip('"')
            pos[0] += 1
            named[name] = kd(params())
        elif t == "NamedMaterial":
            material = named[toks[pos[0]].strip('"')]
            pos[0] += 1
        elif t == "Shape":
            if toks[pos[0]] != '"trianglemesh"':
                fail("shape %s" % toks[pos[0]])
            pos[0] += 1
            p = params()
            P = [float(v) for v in p["P"]]
            pts = []
            for i in range(0, len(P), 3):
                v = [P[i], P[i + 1], P[i + 2], 1]
                pts.append([sum(ctm[r][k] * v[k] for k in range(4)) for r in range(3)])
            idx = [int(v) for v in p["indices"]]
            faces = [idx[i:i + 3] for i in range(0, len(idx), 3)]
            meshes.append((pts, faces, material, light))
        else:
            fail("unsupported directive %r" % t)
    return cam, meshes


# ---------------------------------------------------------------- Mitsuba worker process


def mitsuba_scene(mi, scene_path, work, res, spp, sampler, maxdepth):
    cam, meshes = parse_pbrt(scene_path)
    ex, ey, ez, lx, ly, lz, ux, uy, uz = cam["lookat"]
    # pbrt's camera space is left-handed: mirror x so that Mitsuba's image is not flipped.
    to_world = mi.ScalarTransform4f().look_at(origin=[ex, ey, ez], target=[lx, ly, lz],
                                               up=[ux, uy, uz]) @ mi.ScalarTransform4f().scale([-1, 1, 1])
    scene = {
        "type": "scene",
        # pbrt's maxdepth counts bounces, Mitsuba's max_depth path segments.
        "integrator": {"type": "path", "max_depth": maxdepth + 1},
        "sensor": {"type": "perspective", "fov": cam["fov"], "fov_axis": "smaller",
                   "to_world": to_world,
                   "film": {"type": "hdrfilm", "width": res, "height": res,
                            "rfilter": {"type": "box"}, "pixel_format": "rgb"},
                   "sampler": {"type": sampler, "sample_count": spp}},
    }
    for n, (pts, faces, kd, light) in enumerate(meshes):
        obj = os.path.join(work, "mesh%d.obj" % n)
        with open(obj, "w") as f:
            f.writelines("v %.9g %.9g %.9g\n" % tuple(p) for p in pts)
            f.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in faces)
        shape = {"type": "obj", "filename": obj, "face_normals": True,
                 # pbrt's matte reflects on both sides.
                 "bsdf": {"type": "twosided",
                          "bsdf": {"type": "diffuse",
                                   "reflectance": {"type": "rgb", "value": kd}}}}
        if light:
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": light}}
        scene["mesh%d" % n] = shape
    return scene


def mitsuba_worker(argv):
    """Child process: render once, write the image as raw float32 RGB rows (top first)."""
    scene_path, out, res, spp, sampler, maxdepth, seed, threads = argv
    t0 = time.perf_counter()
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    mi.set_log_level(mi.LogLevel.Error)
    dr.set_thread_count(int(threads))
    t1 = time.perf_counter()
    work = tempfile.mkdtemp(prefix="clr-mitsuba-")
    try:
        scene = mi.load_dict(mitsuba_scene(mi, scene_path, work, int(res), int(spp), sampler,
                                           int(maxdepth)))
    finally:
        shutil.rmtree(work, True)
    actual_spp = scene.sensors()[0].sampler().sample_count()
    t2 = time.perf_counter()
    img = mi.render(scene, seed=int(seed))
    data = bytes(mi.TensorXf(img).numpy().astype("<f4").tobytes())
    t3 = time.perf_counter()
    with open(out, "wb") as f:
        f.write(data)
    print(json.dumps({"spp": actual_spp, "import_s": t1 - t0, "load_s": t2 - t1,
                      "render_s": t3 - t2}))


# ---------------------------------------------------------------- driver


def read_pfm(path):
    """Float RGB triples, top row first (PFM stores the bottom row first)."""
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        s = float(f.readline())
        n = w * h * 3
        v = struct.unpack(("<" if s < 0 else ">") + "f" * n, f.read(4 * n))
    rows = [v[y * w * 3:(y + 1) * w * 3] for y in range(h)]
    return [x for row in reversed(rows) for x in row]


def read_raw(path):
    with open(path, "rb") as f:
        b = f.read()
    return struct.unpack("<%df" % (len(b) // 4), b)


def rel_rmse(x, ref):
    return math.sqrt(sum((a - r) ** 2 / (r * r + 1e-2) for a, r in zip(x, ref)) / len(ref))


def run(cmd, env=None):
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env)
    out = p.stdout.read().decode(errors="replace")
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("compare_mitsuba: %s failed:\n%s" % (" ".join(cmd), out[-3000:]))
    return wall, usage.ru_utime + usage.ru_stime, out


def interp_time(points, target):
    """log-log interpolation of time at the target error between the bracketing sweep points;
    (time, how): 'interp', or 'extrap' from the last two points when none brackets it."""
    pts = sorted(points)  # (spp, time, err)
    if len(pts) < 2:
        return float("nan"), "n/a"
    for (s0, t0, e0), (s1, t1, e1) in zip(pts, pts[1:]):
        if e0 >= target >= e1 and e0 != e1:
            f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0))), "interp"
    a, b = (pts[0], pts[1]) if target > pts[0][2] else (pts[-2], pts[-1])
    f = (math.log(target) - math.log(a[2])) / (math.log(b[2]) - math.log(a[2]))
    return math.exp(math.log(a[1]) + f * (math.log(b[1]) - math.log(a[1]))), "extrap"


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--mitsuba-worker":
        return mitsuba_worker(sys.argv[2:])
    if len(sys.argv) > 1 and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0
    opts = {"clrender": os.path.join(HERE, "..", "build", "clrender"),
            "scene": os.path.join(HERE, "scenes", "cornell.pbrt"), "reps": "3",
            "ref-spp": "1024", "ref-sampler": "sobol", "target-spp": "16", "target-sampler": "sobol", "max-spp": "64",
            "threads": "2", "res": "256", "maxdepth": "5",
            "clr-samplers": "halton sobol zsobol",
            "mi-samplers": "independent stratified multijitter ldsampler"}
    args = sys.argv[1:]
    while args:
        key = args.pop(0)
        if not key.startswith("--") or key[2:] not in opts or not args:
            sys.exit("compare_mitsuba: bad argument %r (see --help)" % key)
        opts[key[2:]] = args.pop(0)
    py = os.environ.get("MITSUBA_PYTHON", sys.executable)
    # numpy too: the worker hands its image over through TensorXf.numpy()
    probe = subprocess.run([py, "-c", "import numpy, mitsuba as mi; mi.set_variant('llvm_ad_rgb'); "
                            "print(mi.__version__)"], capture_output=True, text=True)
    if probe.returncode != 0:
        print("compare_mitsuba: SKIP: Mitsuba 3 with the llvm_ad_rgb variant (and numpy) is not "
              "importable by %s (pip install mitsuba numpy in a venv outside the repository, set "
              "MITSUBA_PYTHON to its python and DRJIT_LIBLLVM_PATH to libLLVM; LLVM 15 is known "
              "to crash it):\n%s" % (py, probe.stderr.strip()[-600:]))
        return 0
    clrender = os.path.abspath(opts["clrender"])
    if not os.access(clrender, os.X_OK):
        sys.exit("compare_mitsuba: clrender binary %s not found (build it first)" % clrender)
    reps, res, threads = int(opts["reps"]), int(opts["res"]), opts["threads"]
    scene_path = os.path.abspath(opts["scene"])
    work = tempfile.mkdtemp(prefix="clr-compare-mitsuba-")
    try:
        return drive(opts, py, probe.stdout.strip(), clrender, scene_path, work, reps, res,
                     threads)
    finally:
        shutil.rmtree(work, True)


def drive(opts, py, mi_version, clrender, scene_path, work, reps, res, threads):
    full = os.path.join(work, "scene.pbrt")
    with open(full, "w") as f:
        f.write('Film "image" "integer xresolution" [%d] "integer yresolution" [%d] '
                '"string filename" "unused.exr"\n' % (res, res))
        f.write('PixelFilter "box"\nIntegrator "path" "integer maxdepth" [%s]\n' % opts["maxdepth"])
        f.write('Include "%s"\n' % scene_path)

    def clr(sampler, spp, seed, out):
        return run([clrender, "render", full, "--sampler", sampler, "--spp", str(spp),
                    "--seed", str(seed), "--nthreads", threads, "--quiet", "--outfile", out])

    def mts(sampler, spp, seed, out):
        wall, cpu, text = run([py, os.path.abspath(__file__), "--mitsuba-worker", scene_path,
                               out, str(res), str(spp), sampler, opts["maxdepth"], str(seed),
                               threads])
        return wall, cpu, text

    print(json.dumps({"mitsuba": mi_version, "variant": "llvm_ad_rgb", "res": res,
                      "threads": int(threads), "maxdepth": int(opts["maxdepth"]),
                      "ref_spp": int(opts["ref-spp"]), "reps": reps,
                      "loadavg": os.getloadavg()[0]}), flush=True)
    ref_path = os.path.join(work, "ref.pfm")
    wall, cpu, _ = clr(opts["ref-sampler"], int(opts["ref-spp"]), 1000, ref_path)
    ref = read_pfm(ref_path)
    print(json.dumps({"reference": "clrender", "sampler": opts["ref-sampler"],
                      "spp": int(opts["ref-spp"]), "wall_s": round(wall, 2),
                      "cpu_s": round(cpu, 2), "mean": sum(ref) / len(ref)}), flush=True)

    sweep = [1 << k for k in range(int(math.log2(int(opts["max-spp"]))) + 1)]
    # Mitsuba rounds these samplers' counts up to squares (ldsampler: powers of 4, at least 4).
    squares = {"stratified": 1, "ldsampler": 4}
    configs = [("clrender", s) for s in opts["clr-samplers"].split()]
    configs += [("mitsuba", s) for s in opts["mi-samplers"].split()]
    samples = {}  # (who, sampler, spp) -> list of (wall, cpu, err, mean, render_s)
    for rep in range(reps):
        for spp in sweep:
            order = configs[rep % len(configs):] + configs[:rep % len(configs)]
            if rep % 2:
                order.reverse()
            for who, sampler in order:
                if who == "mitsuba" and sampler in squares and (
                        spp < squares[sampler] or math.log2(spp) % 2):
                    continue
                if who == "clrender":
                    out = os.path.join(work, "x.pfm")
                    wall, cpu, _ = clr(sampler, spp, rep, out)
                    img, got, render_s = read_pfm(out), spp, None
                else:
                    out = os.path.join(work, "x.raw")
                    wall, cpu, text = mts(sampler, spp, rep, out)
                    st = json.loads([x for x in text.splitlines() if x.startswith('{"spp"')][-1])
                    img, got, render_s = read_raw(out), st["spp"], st["render_s"]
                err = rel_rmse(img, ref)
                samples.setdefault((who, sampler, got), []).append(
                    (wall, cpu, err, sum(img) / len(img), render_s))
                print(json.dumps({"renderer": who, "sampler": sampler, "spp": got, "rep": rep,
                                  "wall_s": round(wall, 3), "cpu_s": round(cpu, 3),
                                  "render_s": render_s and round(render_s, 3),
                                  "rel_rmse": round(err, 5),
                                  "mean_ratio": round(sum(img) / sum(ref), 5),
                                  "loadavg": os.getloadavg()[0]}), flush=True)

    med = {}
    for key, v in samples.items():
        med[key] = {k: statistics.median(x[i] for x in v) for i, k in
                    enumerate(("wall", "cpu", "err", "mean"))}
        if key[0] == "mitsuba":
            med[key]["render"] = statistics.median(x[4] for x in v)
        line = {"median": True, "renderer": key[0], "sampler": key[1], "spp": key[2],
                "n": len(v)}
        line.update({k: round(x, 5) for k, x in med[key].items()})
        print(json.dumps(line), flush=True)

    target_key = ("clrender", opts["target-sampler"], int(opts["target-spp"]))
    if target_key not in med:
        sys.exit("compare_mitsuba: the target %s is not in the sweep" % (target_key,))
    target = med[target_key]["err"]
    ref_mean = sum(ref) / len(ref)
    rows = []
    for who, sampler in configs:
        keys = sorted(k for k in med if k[0] == who and k[1] == sampler)
        top = keys[-1]
        row = {"renderer": who, "sampler": sampler, "target_rel_rmse": round(target, 5),
               "mean_ratio_at_max_spp": round(med[top]["mean"] / ref_mean, 4),
               "max_spp": top[2], "rel_rmse_at_max_spp": round(med[top]["err"], 5)}
        for what in ("wall", "cpu") + (("render",) if who == "mitsuba" else ()):
            t, how = interp_time([(k[2], med[k][what], med[k]["err"]) for k in keys], target)
            row[what + "_s_to_target"] = round(t, 4)
            row["how"] = how
        rows.append(row)
        print(json.dumps(row), flush=True)

    def finite(r, what):
        return r[what + "_s_to_target"] if math.isfinite(r[what + "_s_to_target"]) else math.inf

    best = {w: min((r for r in rows if r["renderer"] == w), key=lambda r: finite(r, "cpu"))
            for w in ("clrender", "mitsuba")}
    print("\ntarget relRMSE %.4f (clrender %s %d spp), reference clrender %s %s spp, %d reps, "
          "%s threads, load %.1f" % (target, opts["target-sampler"], int(opts["target-spp"]),
                                     opts["ref-sampler"], opts["ref-spp"], reps, threads,
                                     os.getloadavg()[0]))
    print("| renderer | sampler | wall s to target | CPU s to target | Mitsuba render-only s "
          "| mean / ref (max spp) | relRMSE at max spp |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print("| %s | %s | %.3f | %.3f | %s | %.4f | %.4f (%d spp) |" % (
            r["renderer"], r["sampler"], r["wall_s_to_target"], r["cpu_s_to_target"],
            "%.3f" % r["render_s_to_target"] if "render_s_to_target" in r else "—",
            r["mean_ratio_at_max_spp"], r["rel_rmse_at_max_spp"], r["max_spp"]))
    summary = {"summary": "best", "clrender": best["clrender"]["sampler"],
               "mitsuba": best["mitsuba"]["sampler"],
               "cpu_ratio": round(best["mitsuba"]["cpu_s_to_target"] /
                                  best["clrender"]["cpu_s_to_target"], 3),
               "wall_ratio": round(min(finite(r, "wall") for r in rows
                                       if r["renderer"] == "mitsuba") /
                                   min(finite(r, "wall") for r in rows
                                       if r["renderer"] == "clrender"), 3)}
    print("\nbest samplers (CPU time): clrender %s, Mitsuba %s: Mitsuba / clrender time to the "
          "target error: CPU %.2fx, wall %.2fx (> 1: clrender faster)" % (
              summary["clrender"], summary["mitsuba"], summary["cpu_ratio"],
              summary["wall_ratio"]))
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
