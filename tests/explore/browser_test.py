#!/usr/bin/env python3
"""`thicket explore` in a real browser: headless Chromium loads the page on a shared scene with
?auto=1 (a heatmap, then the centre pixel's trace), and the DOM it leaves must show the scene
loaded, the statistics filled, boxes and a heatmap drawn, no script error, and the same traversal
as `thicket explain` prints for that ray. Then the page is loaded again and switched to the
kD-tree (?structure=2&depth=3): it must draw as many split planes as the server sends for that
depth, with no script error. Saves both screenshots next to the DOM (docs/explore.md).

usage: browser_test.py THICKET SCENE OUTDIR
With THICKET_EXPLORE_SHOTS=1 it also saves the pictures of the other structures docs/explore.md shows.
Skips (GoogleTest's "[  SKIPPED ]" line, which ctest reports as a skip) only when chromium is absent.
"""
import html as htmllib
import json
import os
import re
import shutil
import subprocess
import sys
import urllib.request


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def body_attrs(html, what):
    """The data-* attributes of the page's <body>, failing on a script error or an unfinished load."""
    body = re.search(r"<body([^>]*)>", html)
    if not body:
        fail("no <body> in chromium's DOM of " + what)
    attrs = dict(re.findall(r'data-([a-z-]+)="([^"]*)"', body.group(1)))
    if "failed" in attrs:
        fail(what + ": the page's script failed: " + attrs["failed"])
    if "errors" in attrs:
        fail(what + ": the page logged errors: " + attrs["errors"])
    if attrs.get("loaded") != "1":
        fail(what + ": the page did not finish loading (data-loaded missing)")
    return attrs


def check_kdtree(common, url, outdir):
    """The page switched to the kD-tree (structure 2) at depth 3 draws the planes the server sends."""
    page = url + "?structure=2&depth=3"
    shot = os.path.join(outdir, "explore-teapot-kdtree.png")
    # One run gives the DOM and the screenshot: the page is loaded once for both.
    run = subprocess.run(common + ["--dump-dom", "--screenshot=" + shot, page], capture_output=True, text=True,
                         timeout=120)
    with open(os.path.join(outdir, "explore-kdtree-dom.html"), "w") as f:
        f.write(run.stdout)
    attrs = body_attrs(run.stdout, "the kd-tree page")
    print("kd-tree page state:", attrs)
    asked = urllib.request.Request(url + "api/nodes", data=b'{"structure": 2, "depth": 3}', method="POST")
    want = json.loads(urllib.request.urlopen(asked, timeout=60).read())
    if want["drawing"] != "planes and leaf cells" or not want["planes"]:
        fail("the server sends no kd-tree planes at depth 3: " + json.dumps(want)[:300])
    if attrs.get("drawing") != want["drawing"]:
        fail("the page draws %r, not the kd-tree's %r" % (attrs.get("drawing"), want["drawing"]))
    # The counts come from the 3D view's geometry, so they need WebGL (swiftshader in CI).
    if attrs.get("webgl") != "ok":
        fail("WebGL is unavailable (%s), so the planes cannot be drawn" % attrs.get("webgl"))
    if int(attrs.get("planes", -1)) != len(want["planes"]) or int(attrs.get("boxes", -1)) != len(want["boxes"]):
        fail("the page drew %s planes and %s leaf cells; the server sent %d and %d" %
             (attrs.get("planes"), attrs.get("boxes"), len(want["planes"]), len(want["boxes"])))
    if not os.path.exists(shot) or os.path.getsize(shot) < 1000:
        fail("no kd-tree screenshot written")
    print("ok: %d kd-tree planes drawn at depth 3; screenshot %s" % (len(want["planes"]), shot))


# The docs' pictures of the other structures (docs/explore.md), made only when asked
# (THICKET_EXPLORE_SHOTS=1): one page load each, beyond what CI needs.
DOC_SHOTS = [("grid", 0), ("grid2", 1), ("octree", 3), ("bsp", 2), ("bih", 4), ("obb", 3), ("tetra", 1)]


def doc_shots(thicket, scene, common, outdir):
    specs = [s for s, _ in DOC_SHOTS]
    args = [thicket, "explore", scene, "--port", "0", "--threads", "2"]
    for spec in specs:
        args += ["--accel", spec]
    server = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        url = next((m.group(1) for m in (re.search(r"explore (http://\S+)", l) for l in server.stdout) if m), None)
        if not url:
            fail("thicket explore printed no URL for the doc shots; stderr: " + server.stderr.read())
        for i, (spec, depth) in enumerate(DOC_SHOTS):
            shot = os.path.join(outdir, "explore-teapot-%s.png" % spec)
            run = subprocess.run(common + ["--dump-dom", "--screenshot=" + shot,
                                           url + "?structure=%d&depth=%d" % (i, depth)],
                                 capture_output=True, text=True, timeout=120)
            attrs = body_attrs(run.stdout, spec + "'s page")
            print("%s at depth %d: %s; screenshot %s" % (spec, depth, {k: attrs.get(k) for k in
                  ("drawing", "boxes", "planes", "oriented", "tetrahedra")}, shot))
    finally:
        server.terminate()
        server.wait(timeout=30)


def main():
    thicket, scene, outdir = sys.argv[1:4]
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if not chromium:
        print("[  SKIPPED ] chromium is not installed (scripts/setup installs Debian's chromium)")
        return 0
    if not os.path.exists(scene):
        print("[  SKIPPED ] %s is absent (the shared scenes live in ../shared/scenes)" % scene)
        return 0
    os.makedirs(outdir, exist_ok=True)
    server = subprocess.Popen([thicket, "explore", scene, "--accel", "bvh", "--accel", "grid", "--accel", "kdtree",
                               "--port", "0", "--threads", "2"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        url = None
        for line in server.stdout:  # the scene and build lines, then the URL
            m = re.search(r"explore (http://\S+)", line)
            if m:
                url = m.group(1)
                break
        if not url:
            fail("thicket explore printed no URL; stderr: " + server.stderr.read())
        page = url + "?auto=1&depth=2&step=3"
        common = [chromium, "--headless", "--no-sandbox", "--disable-gpu-sandbox", "--use-gl=angle",
                  "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--window-size=1200,800",
                  "--virtual-time-budget=30000", "--user-data-dir=" + os.path.join(outdir, "profile")]
        shot = os.path.join(outdir, "explore-teapot.png")
        # One load gives the DOM and the screenshot (chromium writes both once the page settles).
        dom = subprocess.run(common + ["--dump-dom", "--screenshot=" + shot, page], capture_output=True, text=True,
                             timeout=120)
        html = dom.stdout
        with open(os.path.join(outdir, "explore-dom.html"), "w") as f:
            f.write(html)
        body = re.search(r"<body([^>]*)>", html)
        if not body:
            fail("no <body> in chromium's DOM; stderr: " + dom.stderr[-2000:])
        attrs = dict(re.findall(r'data-([a-z-]+)="([^"]*)"', body.group(1)))
        print("page state:", attrs)
        if "failed" in attrs:
            fail("the page's script failed: " + attrs["failed"])
        if "errors" in attrs:
            fail("the page logged errors: " + attrs["errors"])
        if attrs.get("loaded") != "1":
            fail("the page did not finish loading (data-loaded missing)")
        if not attrs.get("scene", "").endswith("teapot.ply"):
            fail("the page names scene %r, not teapot.ply" % attrs.get("scene"))
        info = subprocess.run([thicket, "info", scene, "--accel", "bvh", "--threads", "2"], capture_output=True,
                              text=True, check=True).stdout
        triangles = int(re.search(r"triangles\s+(\d+)", info).group(1))
        if int(attrs.get("mesh-triangles", -1)) != triangles:
            fail("mesh shows %s triangles, the scene has %d" % (attrs.get("mesh-triangles"), triangles))
        nodes = re.search(r"^\s+nodes\s+(\d+)", info, re.M).group(1)
        if not re.search(r"<th>nodes</th><td>%s</td>" % nodes, html):
            fail("the statistics panel lacks `thicket info`'s %s nodes" % nodes)
        if int(attrs.get("boxes", 0)) < 2:
            fail("no boxes drawn at depth 2")
        if attrs.get("heatmap") != "1":
            fail("no heatmap drawn")
        # The hottest pixel the page shows is where the server finds it for the page's request.
        shown = re.search(r'id="heat-caption-0" data-hottest="(\d+),(\d+)"', html)
        request = attrs.get("heat-request")
        if not shown or not request:
            fail("no hottest pixel or heatmap request on the page")
        asked = urllib.request.Request(url + "api/heatmap", data=htmllib.unescape(request).encode(), method="POST")
        server_map = json.loads(urllib.request.urlopen(asked, timeout=60).read())["maps"][0]
        if [int(shown.group(1)), int(shown.group(2))] != server_map["hottest"]:
            fail("the page's hottest pixel %s is not the server's %s" % (shown.groups(), server_map["hottest"]))
        if "webgl" not in attrs:
            fail("the page did not try WebGL")
        # The traversal the page lists is `thicket explain`'s for the same ray.
        listed = re.findall(r'<li class="(enter|cull|skip|prim)[^"]*">\w+ (?:node|primitive) (\d+)', html)
        ray = attrs.get("trace-ray")
        if not ray or not listed:
            fail("no trace listed")
        explained = json.loads(subprocess.run([thicket, "explain", scene, "--accel", "bvh", "--ray", ray,
                                               "--threads", "2"], capture_output=True, text=True, check=True).stdout)
        want = [(s["kind"], s["id"]) for s in explained["steps"]]
        got = [(k, int(i)) for k, i in listed]
        if got != want:
            fail("the page lists %d steps, thicket explain %d; first difference at %s" %
                 (len(got), len(want), next((i for i, (a, b) in enumerate(zip(got, want)) if a != b), min(len(got), len(want)))))
        if not os.path.exists(shot) or os.path.getsize(shot) < 1000:
            fail("no screenshot written")
        print("ok: %d steps match thicket explain; screenshot %s" % (len(got), shot))
        check_kdtree(common, url, outdir)
        if os.environ.get("THICKET_EXPLORE_SHOTS") == "1":
            doc_shots(thicket, scene, common, outdir)
        return 0
    finally:
        server.terminate()  # SIGTERM: the server stops cleanly and exits 0
        try:
            rc = server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()
            fail("thicket explore did not stop on SIGTERM")
        if rc != 0:
            fail("thicket explore exited with %d after SIGTERM; stderr: %s" % (rc, server.stderr.read()[-2000:]))


if __name__ == "__main__":
    sys.exit(main())
