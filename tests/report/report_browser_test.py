#!/usr/bin/env python3
"""report.html in a real browser: a short river run with --png and a watch point writes its
report, and headless Chromium opens it from disk. The test fails when the page logs anything to
the console (errors included), refers to anything outside the file, has a slider that does not
change the picture and the time shown, or shows watch-point arrivals or bank contacts that differ
from spill.json's.

Usage: report_browser_test.py SPILL_SIM SOURCE_DIR   (Python 3 standard library only)
"""
import html.parser
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

BROWSERS = ("chromium", "chromium-browser", "google-chrome")

# Loads the report in a frame, reads its tables, moves the slider from the last picture (where it
# starts) to the first and writes
# what it saw into <pre id="out"> (Chromium's --dump-dom prints the page after its load event,
# which waits for the frame's load handler).
HARNESS = """<!DOCTYPE html><html><body><pre id="out">harness did not run</pre><script>
var frame = document.createElement('iframe');
frame.width = 1000; frame.height = 800;
frame.addEventListener('load', function () {
  var d = frame.contentDocument, out = {};
  function rows(id) {
    var t = d.getElementById(id);
    if (!t) return null;
    return Array.from(t.querySelectorAll('tr')).slice(1).map(function (r) {
      return Array.from(r.querySelectorAll('td')).map(function (c) { return c.textContent; });
    });
  }
  out.arrivals = rows('arrivals');
  out.banks = rows('banks');
  var slider = d.getElementById('map-slider');
  var picture = d.getElementById('map-frame');
  var time = d.getElementById('map-time');
  out.frames = slider ? Number(slider.max) + 1 : 0;
  out.src_before = picture ? picture.getAttribute('src') : null;
  out.time_before = time ? time.textContent : null;
  if (slider) {
    slider.value = '0';
    slider.dispatchEvent(new Event('input'));
  }
  out.src_after = picture ? picture.getAttribute('src') : null;
  out.time_after = time ? time.textContent : null;
  out.picture_loaded = picture ? picture.complete : false;
  document.getElementById('out').textContent = JSON.stringify(out);
});
frame.src = REPORT_URL;
document.body.appendChild(frame);
</script></body></html>
"""


class PreText(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.inside, self.text = False, ""

    def handle_starttag(self, tag, attrs):
        self.inside = tag == "pre" and ("id", "out") in attrs

    def handle_endtag(self, tag):
        self.inside = False

    def handle_data(self, data):
        if self.inside:
            self.text += data


def fail(message):
    print("FAIL:", message)
    sys.exit(1)


def seconds_or(value, none):
    return none if value is None else "%.2f" % value


def main():
    sim, source = sys.argv[1], pathlib.Path(sys.argv[2])
    browser = next((shutil.which(b) for b in BROWSERS if shutil.which(b)), None)
    if not browser:
        fail("no Chromium on PATH (%s): install Debian's chromium (scripts/test.sh does)"
             % ", ".join(BROWSERS))
    with tempfile.TemporaryDirectory() as tmp:
        run = pathlib.Path(tmp) / "run"
        # river_small with its leak early and a watch point 0.8 m downstream of it, so that oil
        # arrives within the short run, and one far away that it never reaches.
        watch = json.dumps([{"name": "intake", "x": 1.8, "y": 0.0, "radius": 0.3},
                            {"name": "far_intake", "x": 3.7, "y": 0.3, "radius": 0.05}])
        cmd = [sim, "run", "--scene", str(source / "configs/scenes/river_small.json"),
               "--out", str(run), "--png", "--threads", "1",
               "--set", "/end_time=2.0", "/leaks/0/start=0.4", "/output/frame_dt=0.1",
               "/watch_points=" + watch]
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        if done.returncode != 0:
            fail("spill-sim run failed: %s\n%s" % (" ".join(cmd), done.stderr[-3000:]))
        report = run / "report.html"
        if not report.exists():
            fail("no report.html in " + str(run))
        page = report.read_text()
        # One file: nothing fetched from anywhere (data: URIs only).
        for pattern in (r'\bsrc="(?!data:)', r'\bhref="', r"<link\b", r"https?://(?!www\.w3\.org/2000/svg)",
                        r"url\("):
            found = re.search(pattern, page)
            if found:
                fail("report.html refers outside itself: %r at %d" % (found.group(0), found.start()))
        spill = json.loads((run / "spill.json").read_text())

        harness = pathlib.Path(tmp) / "harness.html"
        harness.write_text(HARNESS.replace("REPORT_URL", json.dumps(report.as_uri())))
        shot = subprocess.run(
            [browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
             "--allow-file-access-from-files", "--enable-logging=stderr", "--v=0",
             "--user-data-dir=" + str(pathlib.Path(tmp) / "profile"), "--dump-dom",
             harness.as_uri()], capture_output=True, text=True, timeout=180)
        console = [line for line in shot.stderr.splitlines() if "CONSOLE" in line]
        if console:
            fail("the page wrote to the browser console:\n" + "\n".join(console))
        parser = PreText()
        parser.feed(shot.stdout)
        try:
            seen = json.loads(parser.text)
        except ValueError:
            fail("the harness did not report (browser exit %d): %r\n%s"
                 % (shot.returncode, parser.text[:200], shot.stderr[-2000:]))

        # The slider: more than one picture, and moving it changes the picture and the time.
        if seen["frames"] < 2:
            fail("the slider has %d pictures" % seen["frames"])
        if seen["src_before"] == seen["src_after"]:
            fail("moving the slider did not change the picture")
        if seen["time_before"] == seen["time_after"]:
            fail("moving the slider did not change the time shown: %r" % seen["time_after"])
        for key, t in (("time_before", spill["frames"][-1]["t"]), ("time_after", spill["frames"][0]["t"])):
            if not seen[key].startswith("t = %.2f s" % t):
                fail("the %s picture says %r, its frame is at t = %.2f s"
                     % ("last" if key == "time_before" else "first", seen[key], t))

        # The tables say what spill.json says.
        expected = [[name, seconds_or(t, "not reached")] for name, t in spill["arrival_s"].items()]
        if sorted(seen["arrivals"] or []) != sorted(expected):
            fail("arrivals table %r, spill.json %r" % (seen["arrivals"], expected))
        if not any(row[1] != "not reached" for row in expected) or \
                all(row[1] != "not reached" for row in expected):
            fail("the run should have oil reach one watch point and not the other: %r" % expected)
        banks = [row[:2] for row in seen["banks"] or []]
        expected_banks = [["left (+y)", seconds_or(spill["first_left_bank_contact_s"], "none")],
                          ["right (-y)", seconds_or(spill["first_right_bank_contact_s"], "none")]]
        if banks != expected_banks:
            fail("banks table %r, spill.json %r" % (banks, expected_banks))
        print("report.html: %d KB, %d pictures, arrivals %s; no console output"
              % (len(page) // 1024, seen["frames"], expected))


if __name__ == "__main__":
    main()
