#!/usr/bin/env python3
"""`thicket explore` in a real browser, driven as a reader would through the DevTools protocol
(tests/explore/cdp.py: headless Chromium, no other dependency). On one page load over teapot.ply
served with bvh, grid, kdtree and tetra it
- switches structures with the keyboard on the structure <select> and moves the depth slider with
  arrow keys, and each time the 3D view must hold as many boxes or planes as the server sends for
  that structure and depth (the kD-tree at depth 3, the grid, the BVH at depth 2);
- clicks "compute" for the heatmap: the page's hottest pixel must be the server's for the request
  the page sent;
- clicks a pixel of the view: the page must have traced the pixel under the mouse (the server's
  ray for that pixel and camera, which projects back under the mouse through the camera the page
  draws with), and the steps it lists must be `thicket explain`'s for that ray,
  for the BVH and for the tetrahedral walk; "next" steps through them;
- logs no console error, no exception and no failed request.
It saves a screenshot at each stage (docs/explore.md shows them).

usage: browser_test.py THICKET SCENE OUTDIR
With THICKET_EXPLORE_SHOTS=1 it also saves the pictures of the other structures docs/explore.md shows.
Skips (GoogleTest's "[  SKIPPED ]" line, which ctest reports as a skip) only when chromium is absent.
"""
import base64
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time
import urllib.request

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cdp  # noqa: E402

# The structures served, in the page's order: the select's option index is the position here.
STRUCTURES = ["bvh", "grid", "kdtree", "tetra"]
# Key codes Input.dispatchKeyEvent needs for the keys used here.
KEYS = {"ArrowRight": 39, "ArrowLeft": 37, "ArrowDown": 40, "ArrowUp": 38, "Home": 36}


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def post(url, path, body):
    asked = urllib.request.Request(url + path, data=json.dumps(body).encode(), method="POST")
    return json.loads(urllib.request.urlopen(asked, timeout=60).read())


def start_server(thicket, scene, specs):
    args = [thicket, "explore", scene, "--port", "0", "--threads", "2"]
    for spec in specs:
        args += ["--accel", spec]
    server = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in server.stdout:  # the scene and build lines, then the URL
        m = re.search(r"explore (http://\S+)", line)
        if m:
            return server, m.group(1)
    fail("thicket explore printed no URL; stderr: " + server.stderr.read()[-2000:])


def stop_server(server):
    server.terminate()  # SIGTERM: the server stops cleanly and exits 0
    try:
        rc = server.wait(timeout=30)
    except subprocess.TimeoutExpired:
        server.kill()
        fail("thicket explore did not stop on SIGTERM")
    if rc != 0:
        fail("thicket explore exited with %d after SIGTERM; stderr: %s" % (rc, server.stderr.read()[-2000:]))


class Page:
    """The explore page in one browser tab, with the input a reader gives it."""

    def __init__(self, browser):
        self.b = browser

    def settle(self):
        """Waits until no request the page made is pending."""
        self.b.evaluate("window.thicketExplore.settled()")

    def key(self, key, times=1):
        for _ in range(times):
            for kind in ("rawKeyDown", "keyUp"):
                self.b.call("Input.dispatchKeyEvent", type=kind, key=key, code=key,
                            windowsVirtualKeyCode=KEYS[key], nativeVirtualKeyCode=KEYS[key])

    def center(self, element_id):
        return self.b.evaluate("(() => { const r = document.getElementById(%r).getBoundingClientRect();"
                               " return [r.left + r.width / 2, r.top + r.height / 2]; })()" % element_id)

    def click_at(self, x, y):
        self.b.call("Input.dispatchMouseEvent", type="mouseMoved", x=x, y=y)
        for kind in ("mousePressed", "mouseReleased"):
            self.b.call("Input.dispatchMouseEvent", type=kind, x=x, y=y, button="left", buttons=1, clickCount=1)

    def drag(self, dx, dy):
        """Drags across the view from its centre (the page orbits its camera; no pixel is traced)."""
        x, y = (round(v) for v in self.center("gl"))
        self.b.call("Input.dispatchMouseEvent", type="mouseMoved", x=x, y=y)
        self.b.call("Input.dispatchMouseEvent", type="mousePressed", x=x, y=y, button="left", buttons=1, clickCount=1)
        for i in range(1, 11):
            self.b.call("Input.dispatchMouseEvent", type="mouseMoved", x=x + dx * i // 10, y=y + dy * i // 10,
                        button="left", buttons=1)
        self.b.call("Input.dispatchMouseEvent", type="mouseReleased", x=x + dx, y=y + dy, button="left", buttons=1,
                    clickCount=1)

    def click(self, element_id):
        """Scrolls the element into view (the side panel scrolls) and clicks its centre."""
        self.b.evaluate("document.getElementById(%r).scrollIntoView({block: 'center'})" % element_id)
        self.click_at(*self.center(element_id))

    def click_step(self, i):
        """Clicks item i of the listed steps (the page then shows that step)."""
        self.b.evaluate("document.querySelectorAll('#steps li')[%d].id = 'step-item'" % i)
        self.click("step-item")

    def choose_structure(self, index):
        """Focuses the structure <select> and walks its options with the arrow keys, as a reader
        would with the keyboard (a click would open a popup outside the page)."""
        self.b.evaluate("document.getElementById('structure').focus()")
        now = int(self.b.evaluate("document.getElementById('structure').value"))
        self.key("ArrowDown" if index > now else "ArrowUp", abs(index - now))
        self.settle()

    def slide_depth(self, depth):
        """Moves the depth slider to `depth` with Home then ArrowRight: each key is one input event."""
        self.b.evaluate("document.getElementById('depth').focus()")
        self.key("Home")
        self.key("ArrowRight", depth)
        self.settle()

    def drawn(self):
        return self.b.evaluate("window.thicketExplore.state.drawn")

    def screenshot(self, path):
        data = base64.b64decode(self.b.call("Page.captureScreenshot", format="png")["data"])
        with open(path, "wb") as f:
            f.write(data)
        if len(data) < 1000:
            fail("screenshot %s is empty" % path)
        print("  screenshot %s (%d KiB)" % (path, len(data) // 1024))


def check_drawing(page, url, structure, depth, shot):
    """The structure chosen with the keyboard and the slider moved to `depth`: the view holds what
    the server sends for that structure and depth."""
    page.choose_structure(structure)
    page.slide_depth(depth)
    got = page.drawn()
    want = post(url, "api/nodes", {"structure": structure, "depth": depth})
    name = STRUCTURES[structure]
    if got["structure"] != structure or got["depth"] != depth:
        fail("%s: the page draws structure %s at depth %s after the keys for %d at depth %d" %
             (name, got["structure"], got["depth"], structure, depth))
    if got["drawing"] != want["drawing"]:
        fail("%s: the page draws %r, the server %r" % (name, got["drawing"], want["drawing"]))
    for k in ("boxes", "planes", "oriented", "tetrahedra"):
        if got[k] != len(want[k]):
            fail("%s at depth %d: the page holds %d %s, the server sent %d" % (name, depth, got[k], k, len(want[k])))
    print("ok: %s at depth %d: %s (%s)" % (name, depth, want["drawing"],
                                          ", ".join("%d %s" % (got[k], k) for k in ("boxes", "planes") if got[k])))
    page.screenshot(shot)


def check_heatmap(page, url):
    """"compute" clicked: the hottest pixel the page finds is the server's for the same request."""
    page.click("heatmap-button")
    page.settle()
    heat = page.b.evaluate("window.thicketExplore.state.heat")
    if not heat or not heat["hottest"]:
        fail("no heatmap drawn after clicking compute")
    server = post(url, "api/heatmap", heat["request"])["maps"][0]
    if heat["hottest"][0] != server["hottest"]:
        fail("the page's hottest pixel %s is not the server's %s" % (heat["hottest"][0], server["hottest"]))
    print("ok: heatmap's hottest pixel %s is the server's (max %d %s)" %
          (server["hottest"], server["max"], heat["request"]["metric"]))
    return heat["request"]["camera"]


def check_trace(page, url, thicket, scene, structure, fx, fy):
    """A click at fraction (fx, fy) of the view: the page traces the pixel under the mouse, and
    lists `thicket explain`'s steps for that pixel's ray."""
    rect = page.b.evaluate("(() => { const r = document.getElementById('gl').getBoundingClientRect();"
                           " return [r.left, r.top, r.width, r.height]; })()")
    # Mouse events land on whole CSS pixels: the pixel traced is the one under that point.
    x, y = round(rect[0] + fx * rect[2]), round(rect[1] + fy * rect[3])
    before = page.b.evaluate("window.thicketExplore.state.trace")
    page.click_at(x, y)
    page.settle()
    pixel = page.b.evaluate("window.thicketExplore.state.pixel")
    trace = page.b.evaluate("window.thicketExplore.state.trace")
    name = STRUCTURES[structure]
    if not trace or trace == before or pixel["structure"] != structure:
        fail("%s: clicking the view traced nothing new (pixel %s)" % (name, pixel))
    want_pixel = [min(pixel["width"] - 1, int((x - rect[0]) / rect[2] * pixel["width"])),
                  min(pixel["height"] - 1, int((y - rect[1]) / rect[3] * pixel["height"]))]
    if [pixel["x"], pixel["y"]] != want_pixel:
        fail("%s: the click at %d,%d traced pixel %s,%s, not %s" % (name, x, y, pixel["x"], pixel["y"], want_pixel))
    # The server's ray for that pixel of the page's camera is the ray the page lists.
    page.pixel_traced = pixel
    server = post(url, "api/trace", {"structure": structure, "camera": pixel["camera"], "width": pixel["width"],
                                     "height": pixel["height"], "x": pixel["x"], "y": pixel["y"]})
    if server["ray"] != trace["ray"]:
        fail("%s: the page traced ray %s, the server's for the pixel is %s" % (name, trace["ray"], server["ray"]))
    # The ray runs under the mouse through the camera the page draws with (a mirrored or shifted
    # pixel ray passes the checks above): a point along it, as far as the target, projects back
    # onto the click, within one traced pixel (the click need not be at its pixel's centre).
    cam, org, dirn = pixel["camera"], trace["ray"]["org"], trace["ray"]["dir"]
    d = math.dist(cam["eye"], cam["target"])
    point = [org[a] + dirn[a] * d for a in range(3)]
    shown = page.b.evaluate("window.thicketExplore.project(%s)" % json.dumps(point))
    cell = (rect[2] / pixel["width"], rect[3] / pixel["height"])
    if abs(shown[0] - x) > cell[0] + 0.5 or abs(shown[1] - y) > cell[1] + 0.5:
        fail("%s: the click at %d,%d traced a ray the page draws at %.1f,%.1f (a traced pixel is %.1f x %.1f)" %
             (name, x, y, shown[0], shown[1], cell[0], cell[1]))
    # What the list shows, read from the DOM, against `thicket explain` for the same ray.
    items = page.b.evaluate("[...document.querySelectorAll('#steps li')].map((li) => li.textContent)")
    listed = []
    for text in items:
        m = re.fullmatch(r"(enter|cull|skip|prim) (?:node|tetrahedron|primitive) (\d+)(?: t=(\S+))?", text)
        if not m:
            fail("%s: a listed step reads %r" % (name, text))
        listed.append((m.group(1), int(m.group(2)), m.group(3)))
    ray = ",".join(repr(v) for v in trace["ray"]["org"] + trace["ray"]["dir"])
    explained = json.loads(subprocess.run([thicket, "explain", scene, "--accel", name, "--ray", ray, "--threads", "2"],
                                          capture_output=True, text=True, check=True).stdout)
    if not explained["detailed"] or not explained["steps"]:
        fail("%s: thicket explain lists no steps for %s" % (name, ray))
    want = [(s["kind"], s["id"], None if s["t"] is None else "%.5g" % s["t"]) for s in explained["steps"]]
    got = [(k, i, None if t is None else "%.5g" % float(t)) for k, i, t in listed]
    if got != want:
        first = next((i for i, (a, b) in enumerate(zip(got, want)) if a != b), min(len(got), len(want)))
        fail("%s: the page lists %d steps, thicket explain %d; first difference at %d: %s vs %s" %
             (name, len(got), len(want), first, got[first:first + 1], want[first:first + 1]))
    if (explained["hit"] or {}).get("prim") != (trace["hit"] or {}).get("prim"):
        fail("%s: the page's hit %s is not thicket explain's %s" % (name, trace["hit"], explained["hit"]))
    print("ok: %s, pixel (%d, %d): the page lists thicket explain's %d steps (%d nodes, %d primitive tests, hit %s)" %
          (name, pixel["x"], pixel["y"], len(got), explained["nodes"], explained["prims"],
           explained["hit"] and explained["hit"]["prim"]))
    return explained


def step_to(page, k):
    """Clicks "next" k times from the start of the trace; the page names step k."""
    for _ in range(k):
        page.click("next")
    line = page.b.evaluate("document.getElementById('step-line').textContent")
    if not line.startswith("step %d of" % k):
        fail("after %d clicks on next the page shows %r" % (k, line))


def console_errors(events):
    """The errors the page logged: console.error, uncaught exceptions, failed loads."""
    out = []
    for e in events:
        p = e.get("params", {})
        if e["method"] == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            out.append("console.%s: %s" % (p["type"], " ".join(str(a.get("value", a.get("description")))
                                                               for a in p.get("args", []))))
        elif e["method"] == "Runtime.exceptionThrown":
            d = p.get("exceptionDetails", {})
            out.append("exception: " + d.get("exception", {}).get("description", d.get("text", "")))
        elif e["method"] == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
            out.append("log: %s %s" % (p["entry"].get("text"), p["entry"].get("url", "")))
    return out


def open_page(browser, address):
    browser.call("Page.navigate", url=address)
    browser.wait_for("document.body && (document.body.dataset.loaded === '1' || document.body.dataset.failed)",
                     "the page to load")
    failed = browser.evaluate("document.body.dataset.failed || ''")
    if failed:
        fail("the page's script failed: " + failed)
    page = Page(browser)
    page.settle()
    return page


def run(thicket, scene, url, browser, outdir):
    page = open_page(browser, url)
    state = browser.evaluate("({scene: document.body.dataset.scene, webgl: document.body.dataset.webgl,"
                             " triangles: Number(document.body.dataset.meshTriangles),"
                             " nodes: document.querySelector('#stats-table tr:nth-child(3) td')?.textContent})")
    if not state["scene"].endswith("teapot.ply"):
        fail("the page names scene %r, not teapot.ply" % state["scene"])
    if state["webgl"] != "ok":
        fail("WebGL is unavailable (%s): nothing can be drawn" % state["webgl"])
    info = subprocess.run([thicket, "info", scene, "--accel", "bvh", "--threads", "2"], capture_output=True,
                          text=True, check=True).stdout
    if state["triangles"] != int(re.search(r"triangles\s+(\d+)", info).group(1)):
        fail("the mesh shows %s triangles, `thicket info` says otherwise" % state["triangles"])
    nodes = re.search(r"^\s+nodes\s+(\d+)", info, re.M).group(1)
    if state["nodes"] != nodes:
        fail("the statistics show %s bvh nodes, `thicket info` %s" % (state["nodes"], nodes))

    shot = lambda name: os.path.join(outdir, "explore-teapot-%s.png" % name)  # noqa: E731
    check_drawing(page, url, 2, 3, shot("kdtree"))
    check_drawing(page, url, 1, 0, shot("grid"))
    check_drawing(page, url, 0, 2, shot("bvh"))
    camera = check_heatmap(page, url)
    page.click("overlay-on")  # the heatmap off, so the ray and its boxes show
    bvh = check_trace(page, url, thicket, scene, 0, 0.58, 0.44)
    if page.pixel_traced["camera"] != camera:
        fail("the page traced with camera %s, its heatmap's was %s" % (page.pixel_traced["camera"], camera))
    step_to(page, min(4, len(bvh["steps"])))
    # Seen from the eye, the ray is a point: the camera orbited (a drag) shows it from the side.
    page.drag(-160, 40)
    if page.b.evaluate("window.thicketExplore.state.pixel") != page.pixel_traced:
        fail("dragging the view traced a pixel")
    page.screenshot(shot("bvh-trace"))

    # The tetrahedral walk of an off-centre pixel's ray in the orbited view: the structure hidden, so
    # the walked tetrahedra stand out, then the camera orbited again and zoomed, the trace kept.
    page.choose_structure(3)
    page.click("nodes-on")
    tetra = check_trace(page, url, thicket, scene, 3, 0.44, 0.55)
    walked = [s for s in tetra["steps"] if s["kind"] == "enter"]
    if len(walked) < 2:
        fail("the tetrahedral walk enters %d tetrahedra" % len(walked))
    page.click_step(len(tetra["steps"]) - 1)
    line = browser.evaluate("document.getElementById('step-line').textContent")
    if not line.startswith("step %d of" % len(tetra["steps"])):
        fail("clicking the last step shows %r" % line)
    page.drag(-160, 40)
    cx, cy = (round(v) for v in page.center("gl"))
    browser.call("Input.dispatchMouseEvent", type="mouseWheel", x=cx, y=cy, deltaX=0, deltaY=-700)
    page.screenshot(shot("tetra-walk"))
    print("ok: the walk through %d tetrahedra is drawn" % len(walked))


# The docs' pictures of the other structures (docs/explore.md), made only when asked
# (THICKET_EXPLORE_SHOTS=1): one page load each, beyond what CI needs.
DOC_SHOTS = [("grid2", 1), ("octree", 3), ("bsp", 2), ("bih", 4), ("obb", 3), ("tetra", 1)]


def doc_shots(thicket, scene, browser, outdir):
    server, url = start_server(thicket, scene, [s for s, _ in DOC_SHOTS])
    try:
        for i, (spec, depth) in enumerate(DOC_SHOTS):
            page = open_page(browser, url + "?structure=%d&depth=%d" % (i, depth))
            print("%s at depth %d: %s" % (spec, depth, page.drawn()))
            page.screenshot(os.path.join(outdir, "explore-teapot-%s.png" % spec))
    finally:
        stop_server(server)


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
    start = time.time()
    server, url = start_server(thicket, scene, STRUCTURES)
    browser = None
    try:
        # swiftshader stands in for a GPU, so WebGL works on a machine without one.
        browser = cdp.Browser(chromium, os.path.join(outdir, "profile"),
                              ["--no-sandbox", "--use-gl=angle", "--use-angle=swiftshader",
                               "--enable-unsafe-swiftshader", "--window-size=1000,640", "--hide-scrollbars",
                               "--mute-audio"])
        for domain in ("Page", "Runtime", "Log"):
            browser.call(domain + ".enable")
        run(thicket, scene, url, browser, outdir)
        if os.environ.get("THICKET_EXPLORE_SHOTS") == "1":
            doc_shots(thicket, scene, browser, outdir)
        errors = console_errors(browser.events)
        if errors:
            fail("the page logged %d error(s): %s" % (len(errors), "; ".join(errors)[:2000]))
        print("ok: no console error; %.1f s" % (time.time() - start))
        return 0
    finally:
        if browser:
            browser.close()
        stop_server(server)


if __name__ == "__main__":
    sys.exit(main())
