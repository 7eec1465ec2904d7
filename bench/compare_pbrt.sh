#!/bin/bash
# Side-by-side comparison with pbrt-v3 or pbrt-v4 (built from their own repositories, outside
# this one):
#
#   bench/compare_pbrt.sh PATH_TO_PBRT [--clrender PATH] [--reps N] [--scenes "cornell sphere star"]
#                         [--integrators "ao1 ao64 direct path"] [--samplers "halton sobol"]
#                         [--spp N] [--threads N] [--res N] [--peer-version 3|4]
#
# Renders each bundled comparison scene (bench/scenes/: the Cornell box, a sphere under a point
# light, a star of thin triangles) with each integrator (ambientocclusion with 1 and 64
# directions, directlighting, path) and sampler at 256x256, 16 spp, box filter, 2 threads, with
# clrender and pbrt (both --quiet) interleaved (the order alternates per repetition), and prints
# one JSON line per case: both medians of the wall time, the ratio pbrt / clrender (> 1: clrender
# faster), rays traced, CPU seconds (user + system) and their ratio, peak RSS; then a summary
# table with the geometric means. The machine may be shared: only ratios measured in the same run
# mean anything, the medians tame the noise, and on a loaded machine the CPU ratio is the
# steadier figure.
#
# pbrt-v4 (told apart by its --upgrade option, or named by --peer-version 4) renders the scenes
# as its own `pbrt --upgrade` writes them; clrender then runs pbrt-v4's samplers (--seeding
# pbrt-v4, their default randomizations). pbrt-v4's ambientocclusion takes one direction per
# camera sample, so ao64 is skipped; `direct` is what its upgrade makes of directlighting, a
# path of depth 1.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [ $# -lt 1 ] || [ "$1" = "--help" ] || [ "$1" = "-h" ]; then
  awk 'NR > 1 && !/^#/ { exit } NR > 1' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
  exit 2
fi
pbrt="$1"
shift
if [ ! -x "$pbrt" ]; then
  echo "compare_pbrt: pbrt binary \"$pbrt\" not found or not executable (build pbrt-v3 or" \
    "pbrt-v4 from https://github.com/mmp/pbrt-v3 or pbrt-v4 outside this repository)" >&2
  exit 2
fi
if ! command -v python3 > /dev/null; then
  echo "compare_pbrt: needs python3" >&2
  exit 2
fi
exec python3 - "$here" "$pbrt" "$@" << 'PYTHON'
import atexit, json, math, os, re, shutil, statistics, subprocess, sys, tempfile, time

here, pbrt = sys.argv[1], sys.argv[2]
opts = {"clrender": os.path.join(here, "..", "build", "clrender"), "reps": "3",
        "scenes": "cornell sphere star", "integrators": "ao1 ao64 direct path",
        "samplers": "halton sobol", "spp": "16", "threads": "2", "res": "256", "peer-version": ""}
args = sys.argv[3:]
while args:
    key = args.pop(0)
    if not key.startswith("--") or key[2:] not in opts or not args:
        sys.exit("compare_pbrt: bad argument %r (see --help)" % key)
    opts[key[2:]] = args.pop(0)
clrender = os.path.abspath(opts["clrender"])
if not os.access(clrender, os.X_OK):
    sys.exit("compare_pbrt: clrender binary %s not found (build it first)" % clrender)
reps, spp, threads, res = (int(opts[k]) for k in ("reps", "spp", "threads", "res"))
version = opts["peer-version"]
if not version:  # pbrt-v4 has --upgrade, pbrt-v3 does not
    usage = subprocess.run([pbrt, "--help"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           timeout=60).stdout.decode(errors="replace")
    version = "4" if "--upgrade" in usage else "3"
if version not in ("3", "4"):
    sys.exit("compare_pbrt: --peer-version %r: expected 3 or 4" % version)
peer, key = "pbrt-v" + version, "pbrt_v" + version
integrators = {
    "ao1": 'Integrator "ambientocclusion" "integer nsamples" [1]',
    "ao64": 'Integrator "ambientocclusion" "integer nsamples" [64]',
    "direct": 'Integrator "directlighting"',
    "path": 'Integrator "path" "integer maxdepth" [5]',
}
# pbrt-v4's ambientocclusion has no nsamples: one direction per camera sample
v4_integrators = dict(integrators, ao1='Integrator "ambientocclusion"')
work = tempfile.mkdtemp(prefix="clr-compare-")
atexit.register(shutil.rmtree, work, True)


def write_scene(path, integrator, sampler, body):
    with open(path, "w") as f:
        f.write('Film "image" "integer xresolution" [%d] "integer yresolution" [%d] '
                '"string filename" "%s"\n' % (res, res, path[:-5] + ".exr"))
        f.write('Sampler "%s" "integer pixelsamples" [%d]\n' % (sampler, spp))
        f.write('PixelFilter "box"\n%s\n' % integrator)
        if body:
            f.write('Include "%s"\n' % body)


def upgraded(v3_path, v4_path):
    """pbrt-v4's --upgrade of a pbrt-v3 file, written to v4_path."""
    p = subprocess.run([pbrt, "--upgrade", v3_path], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, timeout=60)
    if p.returncode != 0:
        sys.exit("compare_pbrt: %s --upgrade %s failed (%d):\n%s" % (
            pbrt, v3_path, p.returncode, p.stderr.decode(errors="replace")[-2000:]))
    with open(v4_path, "wb") as f:
        f.write(p.stdout)
    return v4_path


def scene_files(scene, integ, sampler):
    """The scene clrender renders (pbrt-v3's format) and the one the peer renders."""
    body = os.path.join(here, "scenes", scene + ".pbrt")
    path = os.path.join(work, "%s-%s-%s.pbrt" % (scene, integ, sampler))
    write_scene(path, integrators[integ], sampler, body)
    if version == "3":
        return path, path
    v4_body = os.path.join(work, scene + "-body-v4.pbrt")
    if not os.path.exists(v4_body):
        upgraded(body, v4_body)
    head = os.path.join(work, "%s-%s-%s-head.pbrt" % (scene, integ, sampler))
    write_scene(head, v4_integrators[integ], sampler, None)
    v4_path = upgraded(head, path[:-5] + "-v4.pbrt")
    with open(v4_path, "a") as f:
        f.write('Include "%s"\n' % v4_body)
    return path, v4_path


def run(cmd):
    """Wall seconds, CPU seconds (user + system), peak RSS (MB) and output of one child."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, cwd=work)
    out = p.stdout.read().decode(errors="replace")
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit("compare_pbrt: %s failed (%d):\n%s" % (" ".join(cmd), p.returncode, out[-2000:]))
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0, out


def clrender_rays(out):
    m = re.search(r'"rays":(\d+)', out)
    return int(m.group(1)) if m else None


def pbrt_rays(out):
    """Regular plus shadow ray intersection tests from pbrt's statistics."""
    total = 0
    for name in ("Regular ray intersection tests", "Shadow ray intersection tests"):
        m = re.search(re.escape(name) + r"\s+(\d+)", out)
        total += int(m.group(1)) if m else 0
    return total or None


cases = [(s, i, m) for s in opts["scenes"].split() for i in opts["integrators"].split()
         for m in opts["samplers"].split()]
if version == "4" and any(i == "ao64" for _, i, _ in cases):
    print("compare_pbrt: ao64 skipped: pbrt-v4's ambientocclusion traces one direction per "
          "camera sample", file=sys.stderr)
    cases = [c for c in cases if c[1] != "ao64"]
results = []
for scene, integ, sampler in cases:
    path, peer_path = scene_files(scene, integ, sampler)
    cl_cmd = [clrender, "render", path, "--nthreads", str(threads), "--quiet", "--stats"]
    if version == "4":
        cl_cmd += ["--seeding", "pbrt-v4"]
    # Both quiet: pbrt-v3's progress thread sleeps in 250 ms steps and is joined at the end, which
    # would add up to 0.25 s to its wall time; its statistics (the ray count) need a loud run.
    pb_cmd = [pbrt, "--nthreads", str(threads), "--quiet", peer_path]
    stats = ["--stats"] if version == "4" else []  # pbrt-v3 prints them unless --quiet
    loud = [pbrt, "--nthreads", str(threads)] + stats + [peer_path]
    rays = {"pbrt": pbrt_rays(run(loud)[3])}
    t = {"clrender": [], "pbrt": []}
    cpu = {"clrender": [], "pbrt": []}
    rss = {"clrender": [], "pbrt": []}
    for rep in range(reps):
        order = [("clrender", cl_cmd), ("pbrt", pb_cmd)]
        if rep % 2:
            order.reverse()
        for who, cmd in order:
            wall, cpu_s, peak, out = run(cmd)
            t[who].append(wall)
            cpu[who].append(cpu_s)
            rss[who].append(peak)
            if who == "clrender":
                rays[who] = clrender_rays(out)
    line = {"scene": scene, "integrator": integ, "sampler": sampler, "res": res, "spp": spp,
            "threads": threads, "reps": reps,
            "clrender_s": round(statistics.median(t["clrender"]), 4),
            key + "_s": round(statistics.median(t["pbrt"]), 4),
            "clrender_cpu_s": round(statistics.median(cpu["clrender"]), 4),
            key + "_cpu_s": round(statistics.median(cpu["pbrt"]), 4),
            "clrender_rays": rays["clrender"], key + "_rays": rays["pbrt"],
            "clrender_peak_rss_mb": round(max(rss["clrender"]), 1),
            key + "_peak_rss_mb": round(max(rss["pbrt"]), 1)}
    if version == "4":
        line["clrender_seeding"] = "pbrt-v4"
    line["speedup"] = round(line[key + "_s"] / line["clrender_s"], 3)
    line["cpu_ratio"] = round(line[key + "_cpu_s"] / line["clrender_cpu_s"], 3)
    results.append(line)
    print(json.dumps(line), flush=True)

print("\n| scene | integrator | sampler | clrender s | %s s | speed-up | CPU s clr / pbrt "
      "| CPU ratio | rays clr / pbrt | RSS MB clr / pbrt |" % peer)
print("|---|---|---|---|---|---|---|---|---|---|")
for r in results:
    ray_ratio = ("%.2f" % (r["clrender_rays"] / r[key + "_rays"])
                 if r["clrender_rays"] and r[key + "_rays"] else "?")
    print("| %s | %s | %s | %.3f | %.3f | %.2fx | %.2f / %.2f | %.2fx | %s | %.0f / %.0f |" % (
        r["scene"], r["integrator"], r["sampler"], r["clrender_s"], r[key + "_s"], r["speedup"],
        r["clrender_cpu_s"], r[key + "_cpu_s"], r["cpu_ratio"], ray_ratio,
        r["clrender_peak_rss_mb"], r[key + "_peak_rss_mb"]))


def geomean(key):
    return math.exp(sum(math.log(r[key]) for r in results) / len(results))


print("\ngeometric mean over %d cases (medians of %d interleaved runs): wall-time speed-up %.2fx, "
      "CPU-time ratio %.2fx (%s / clrender)" % (len(results), reps, geomean("speedup"),
                                                geomean("cpu_ratio"), peer))
print(json.dumps({"summary": "geomean", "peer": peer, "cases": len(results),
                  "speedup": round(geomean("speedup"), 3),
                  "cpu_ratio": round(geomean("cpu_ratio"), 3)}))
PYTHON
