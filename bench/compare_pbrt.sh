#!/bin/bash
# Side-by-side comparison with pbrt-v3 (built from its own repository, outside this one):
#
#   bench/compare_pbrt.sh PATH_TO_PBRT [--clrender PATH] [--reps N] [--scenes "cornell sphere star"]
#                         [--integrators "ao1 ao64 direct path"] [--samplers "halton sobol"]
#                         [--spp N] [--threads N] [--res N]
#
# Renders each bundled comparison scene (bench/scenes/: the Cornell box, a sphere under a point
# light, a star of thin triangles) with each integrator (ambientocclusion with 1 and 64
# directions, directlighting, path) and sampler at 256x256, 16 spp, box filter, 2 threads, with
# clrender and pbrt-v3 (both --quiet) interleaved (the order alternates per repetition), and
# prints one JSON line per case: both medians of the wall time, the ratio pbrt / clrender (> 1: clrender faster), rays
# traced, CPU seconds (user + system) and their ratio, peak RSS; then a summary table with the
# geometric means. The machine may be shared: only ratios measured in the same run mean anything,
# the medians tame the noise, and on a loaded machine the CPU ratio is the steadier figure.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [ $# -lt 1 ] || [ "$1" = "--help" ] || [ "$1" = "-h" ]; then
  sed -n '2,15p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
  exit 2
fi
pbrt="$1"
shift
if [ ! -x "$pbrt" ]; then
  echo "compare_pbrt: pbrt-v3 binary \"$pbrt\" not found or not executable (build pbrt-v3 from" \
    "https://github.com/mmp/pbrt-v3 outside this repository)" >&2
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
        "samplers": "halton sobol", "spp": "16", "threads": "2", "res": "256"}
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
integrators = {
    "ao1": 'Integrator "ambientocclusion" "integer nsamples" [1]',
    "ao64": 'Integrator "ambientocclusion" "integer nsamples" [64]',
    "direct": 'Integrator "directlighting"',
    "path": 'Integrator "path" "integer maxdepth" [5]',
}
work = tempfile.mkdtemp(prefix="clr-compare-")
atexit.register(shutil.rmtree, work, True)


def scene_file(scene, integ, sampler):
    body = os.path.join(here, "scenes", scene + ".pbrt")
    path = os.path.join(work, "%s-%s-%s.pbrt" % (scene, integ, sampler))
    with open(path, "w") as f:
        f.write('Film "image" "integer xresolution" [%d] "integer yresolution" [%d] '
                '"string filename" "%s"\n' % (res, res, path[:-5] + ".exr"))
        f.write('Sampler "%s" "integer pixelsamples" [%d]\n' % (sampler, spp))
        f.write('PixelFilter "box"\n%s\nInclude "%s"\n' % (integrators[integ], body))
    return path


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
    """Regular plus shadow ray intersection tests from pbrt-v3's statistics."""
    total = 0
    for name in ("Regular ray intersection tests", "Shadow ray intersection tests"):
        m = re.search(re.escape(name) + r"\s+(\d+)", out)
        total += int(m.group(1)) if m else 0
    return total or None


cases = [(s, i, m) for s in opts["scenes"].split() for i in opts["integrators"].split()
         for m in opts["samplers"].split()]
results = []
for scene, integ, sampler in cases:
    path = scene_file(scene, integ, sampler)
    cl_cmd = [clrender, "render", path, "--nthreads", str(threads), "--quiet", "--stats"]
    # Both quiet: pbrt-v3's progress thread sleeps in 250 ms steps and is joined at the end, which
    # would add up to 0.25 s to its wall time; its statistics (the ray count) need a loud run.
    pb_cmd = [pbrt, "--nthreads", str(threads), "--quiet", path]
    rays = {"pbrt": pbrt_rays(run([pbrt, "--nthreads", str(threads), path])[3])}
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
            "pbrt_v3_s": round(statistics.median(t["pbrt"]), 4),
            "clrender_cpu_s": round(statistics.median(cpu["clrender"]), 4),
            "pbrt_v3_cpu_s": round(statistics.median(cpu["pbrt"]), 4),
            "clrender_rays": rays["clrender"], "pbrt_v3_rays": rays["pbrt"],
            "clrender_peak_rss_mb": round(max(rss["clrender"]), 1),
            "pbrt_v3_peak_rss_mb": round(max(rss["pbrt"]), 1)}
    line["speedup"] = round(line["pbrt_v3_s"] / line["clrender_s"], 3)
    line["cpu_ratio"] = round(line["pbrt_v3_cpu_s"] / line["clrender_cpu_s"], 3)
    results.append(line)
    print(json.dumps(line), flush=True)

print("\n| scene | integrator | sampler | clrender s | pbrt-v3 s | speed-up | CPU s clr / pbrt "
      "| CPU ratio | rays clr / pbrt | RSS MB clr / pbrt |")
print("|---|---|---|---|---|---|---|---|---|---|")
for r in results:
    ray_ratio = ("%.2f" % (r["clrender_rays"] / r["pbrt_v3_rays"])
                 if r["clrender_rays"] and r["pbrt_v3_rays"] else "?")
    print("| %s | %s | %s | %.3f | %.3f | %.2fx | %.2f / %.2f | %.2fx | %s | %.0f / %.0f |" % (
        r["scene"], r["integrator"], r["sampler"], r["clrender_s"], r["pbrt_v3_s"], r["speedup"],
        r["clrender_cpu_s"], r["pbrt_v3_cpu_s"], r["cpu_ratio"], ray_ratio,
        r["clrender_peak_rss_mb"], r["pbrt_v3_peak_rss_mb"]))


def geomean(key):
    return math.exp(sum(math.log(r[key]) for r in results) / len(results))


print("\ngeometric mean over %d cases (medians of %d interleaved runs): wall-time speed-up %.2fx, "
      "CPU-time ratio %.2fx (pbrt-v3 / clrender)" % (len(results), reps, geomean("speedup"),
                                                     geomean("cpu_ratio")))
print(json.dumps({"summary": "geomean", "cases": len(results), "speedup": round(geomean("speedup"), 3),
                  "cpu_ratio": round(geomean("cpu_ratio"), 3)}))
PYTHON
