#!/usr/bin/env python3
"""sets-diagnose --report writes an index.html that a browser loads with every image decoded.

Usage: report_html_chromium_test.py SETS_DIAGNOSE OUT_DIR
Runs the built-in example into OUT_DIR/report, then headless Chromium (Debian `chromium`):
  1. --dump-dom of a copy of the page with a script that records, after the load event, each
     image's naturalWidth x naturalHeight (0 x 0 = not decoded);
  2. --screenshot of the page itself (OUT_DIR/report_screenshot.png, kept for a person to look at),
     checked to be a PNG of the window's size that is not blank.
Exit 77 (ctest: skipped) when chromium is not installed. Standard library only.
"""

import pathlib
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--virtual-time-budget=15000"]


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def chromium(args, profile):
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    r = subprocess.run([exe, *FLAGS, "--user-data-dir=" + str(profile), *args], capture_output=True, text=True,
                       timeout=180)
    if r.returncode != 0:
        fail("chromium exited %d: %s" % (r.returncode, r.stderr[-2000:]))
    return r.stdout


def png_size_and_variety(path):
    data = pathlib.Path(path).read_bytes()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail("%s is not a PNG" % path)
    w, h = struct.unpack(">II", data[16:24])
    idat, pos = b"", 8
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        if kind == b"IDAT":
            idat += data[pos + 8:pos + 8 + n]
        pos += 12 + n
    raw = zlib.decompress(idat)
    return w, h, len(set(raw[:: max(1, len(raw) // 200000)]))


def main():
    if len(sys.argv) != 3:
        fail(__doc__)
    exe, out = sys.argv[1], pathlib.Path(sys.argv[2])
    if not (shutil.which("chromium") or shutil.which("chromium-browser")):
        print("SKIP: chromium is not installed (Debian package `chromium`)")
        sys.exit(77)
    report = out / "report"
    shutil.rmtree(report, ignore_errors=True)
    out.mkdir(parents=True, exist_ok=True)  # a fresh build folder does not have it
    r = subprocess.run([exe, "--example", "--quiet", "--report", str(report)], capture_output=True, text=True)
    if r.returncode != 0:
        fail("sets-diagnose exited %d: %s" % (r.returncode, r.stderr))
    page = report / "index.html"
    html = page.read_text(encoding="utf-8")
    images = re.findall(r'<img src="([^"]+)"', html)
    if len(images) < 3:
        fail("expected the signal and signature figures, found %s" % images)
    for img in images:
        if not (report / img).is_file():
            fail("the page shows %s, which is not beside it" % img)
    if re.search(r'(src|href)="(https?:)?//', html) or "<script" in html:
        fail("the page is not self-contained (external resource or script)")
    for must in ("Verdict:", "coulomb_friction", "bounded-error interval", "statistical 95", "not guaranteed"):
        if must not in html:
            fail("the page does not say %r" % must)

    probe = report / "index.probe.html"
    probe.write_text(html.replace("</body>", """<script>
window.addEventListener('load', function () {
  var s = [];
  for (var i = 0; i < document.images.length; ++i) {
    var im = document.images[i];
    s.push((im.complete ? im.naturalWidth : 0) + 'x' + (im.complete ? im.naturalHeight : 0));
  }
  document.body.setAttribute('data-images', s.join(' '));
});
</script></body>"""), encoding="utf-8")
    with tempfile.TemporaryDirectory() as profile:
        dom = chromium(["--dump-dom", probe.as_uri()], profile)
    probe.unlink()
    m = re.search(r'data-images="([^"]*)"', dom)
    if not m:
        fail("the page did not finish loading (no load event in the dumped DOM)")
    sizes = m.group(1).split()
    if len(sizes) != len(images):
        fail("the browser found %d images, the page has %d" % (len(sizes), len(images)))
    for img, s in zip(images, sizes):
        w, h = map(int, s.split("x"))
        if w < 100 or h < 100:
            fail("%s was not decoded by the browser (%s)" % (img, s))

    shot = out / "report_screenshot.png"
    with tempfile.TemporaryDirectory() as profile:
        chromium(["--window-size=1280,2400", "--screenshot=" + str(shot), page.as_uri()], profile)
    w, h, variety = png_size_and_variety(shot)
    if (w, h) != (1280, 2400):
        fail("screenshot is %dx%d, expected 1280x2400" % (w, h))
    if variety < 20:
        fail("the screenshot is blank (%d distinct byte values)" % variety)
    print("OK: %d images decoded (%s); screenshot %s (%dx%d)" % (len(images), " ".join(sizes), shot, w, h))


if __name__ == "__main__":
    main()
