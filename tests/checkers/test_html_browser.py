"""verify's HTML report in a real headless browser (slow; needs Debian's `chromium`:
`apt-get install chromium`).  The page loads, every row of the matrix renders, the pictures
decode, a screenshot is taken, and the page makes no network request (Chromium's own network
log, with a negative control that shows the check can fail)."""

from __future__ import annotations

import json
import shutil
import subprocess

import pytest

from swarmproof.checkers.html_report import write_html
from swarmproof.checkers.report import Report, section_exploration, section_lattices

pytestmark = pytest.mark.slow

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run", "--disable-default-apps",
         "--metrics-recording-only", "--disable-breakpad"]


def chromium() -> str:
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        pytest.fail("the browser test needs Debian's chromium: apt-get install chromium")
    return exe


def urls_requested(exe, page, tmp_path) -> list[str]:
    """Every URL the page asked Chromium's network stack for while it loaded (its NetLog)."""
    log = tmp_path / f"{page.stem}-netlog.json"
    subprocess.run([exe, *FLAGS, f"--log-net-log={log}", "--virtual-time-budget=3000", "--dump-dom",
                    page.as_uri()], capture_output=True, text=True, timeout=120)
    text = log.read_text()
    try:
        doc = json.loads(text)
    except json.JSONDecodeError:               # Chromium may leave the events list open
        doc = json.loads(text.rstrip().rstrip(",") + "]}")
    urls = []
    for ev in doc.get("events", []):
        params = ev.get("params") or {}
        # a request the page made carries its initiator (a file page's is "null"); Chromium's own
        # background requests (time, dictionaries, accounts) say "not an origin"
        if isinstance(params.get("url"), str) and "initiator" in params and params["initiator"] != "not an origin":
            urls.append(params["url"])
    return urls


def test_report_renders_and_makes_no_network_request(tmp_path):
    exe = chromium()
    rows = (section_lattices()[:3]
            + section_exploration(algorithms=["song2014"], properties=["tree_links"], max_examples=30, robots=(3, 4)))
    page = tmp_path / "report.html"
    write_html(Report(rows), page)
    dom = subprocess.run([exe, *FLAGS, "--virtual-time-budget=3000", "--dump-dom", page.as_uri()],
                         capture_output=True, text=True, timeout=120).stdout
    assert dom.count('<tr class="row ') == len(rows)
    assert "verify: VIOLATED" in dom and "song2014 n=3..4" in dom
    shot = tmp_path / "shot.png"
    subprocess.run([exe, *FLAGS, f"--screenshot={shot}", "--window-size=1200,1600", page.as_uri()],
                   capture_output=True, text=True, timeout=120)
    from PIL import Image

    img = Image.open(shot).convert("L")
    assert img.size == (1200, 1600)
    lo, hi = img.getextrema()
    assert hi - lo > 100                                   # not a blank page
    remote = [u for u in urls_requested(exe, page, tmp_path) if not u.startswith(("file:", "data:"))]
    assert remote == []
    # negative control: a page that does fetch something is seen doing it
    leaky = tmp_path / "leaky.html"
    leaky.write_text('<!DOCTYPE html><html><body><img src="http://127.0.0.1:9/x.png"></body></html>')
    assert any(u.startswith("http://127.0.0.1:9/") for u in urls_requested(exe, leaky, tmp_path))
