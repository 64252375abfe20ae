"""One self-contained HTML report of ``swarmproof verify`` (``--html FILE``).

The page holds the property matrix (every row with its verdict, its status
against the baseline or the claims, its citation and detail); for each
violated row with a counterexample, the counterexample as steps, a picture of
the replayed run (trajectories, the violation marked) and its animation
(GIF); for each lattice row, the lattice checker's picture.  Everything is
inline -- styles, and pictures as ``data:`` URLs -- and a Content-Security-Policy
forbids any other source, so the page makes no network request (checked in a
headless browser by the slow test ``tests/checkers/test_html_browser.py``).
No script; no wall-clock time, so the same run gives the same bytes.
"""

from __future__ import annotations

import base64
import html
import os
import tempfile

from swarmproof.models.verdict import Verdict

__all__ = ["render_html", "write_html", "CSP"]

#: Nothing but inline styles and ``data:`` images.
CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'"

_STYLE = """
body { font-family: system-ui, sans-serif; margin: 1.5em; color: #222; }
h1 { font-size: 1.4em; } h2 { font-size: 1.15em; margin-top: 1.6em; }
.summary { font-weight: bold; padding: .5em .8em; border-radius: 4px; background: #eef; }
.summary.fail { background: #fdd; } .summary.pass { background: #dfd; } .summary.inconclusive { background: #ffd; }
table { border-collapse: collapse; font-size: .85em; width: 100%; }
th, td { border: 1px solid #ccc; padding: .25em .45em; text-align: left; vertical-align: top; }
th { background: #f4f4f4; }
tr.failure td.status { background: #f8c9c9; } tr.error td.status { background: #f9eeb0; }
tr.skipped td.status { background: #e6e6e6; } tr.na td { color: #777; } tr.passed td.status { background: #cfeccf; }
pre { background: #f7f7f7; padding: .6em; overflow-x: auto; font-size: .85em; }
.pictures img { max-width: 46%; margin-right: 2%; border: 1px solid #ddd; vertical-align: top; }
.cx { border-top: 1px solid #ccc; margin-top: 1em; }
"""


def _esc(text) -> str:
    return html.escape(str(text), quote=True)


def _txt(text) -> str:
    """Text a person reads: citations as papers ("Song & O'Kane 2016, Lemma 11"), escaped."""
    from swarmproof.models.citations import readable

    return _esc(readable(str(text)))


def _img(data: bytes, mime: str, alt: str) -> str:
    return f'<img alt="{_esc(alt)}" src="data:{mime};base64,{base64.b64encode(data).decode("ascii")}">'


def _replay_pictures(cx, tmp: str, stem: str) -> tuple[list[str], str]:
    """``(img tags, note)`` for one counterexample: the picture and the animation of its replay."""
    from swarmproof.checkers.replay import gif_replay, plot_replay, replay
    from swarmproof.models.errors import SwarmproofError

    try:
        rr = replay(cx)
        png = plot_replay(rr, os.path.join(tmp, stem + ".png"))
        gif = gif_replay(rr, os.path.join(tmp, stem + ".gif"))
    except SwarmproofError as exc:
        return [], f"could not replay it to draw it: {exc}"
    tags = []
    with open(png, "rb") as fh:
        tags.append(_img(fh.read(), "image/png", f"{cx.algorithm} {cx.property}: trajectories"))
    with open(gif, "rb") as fh:
        tags.append(_img(fh.read(), "image/gif", f"{cx.algorithm} {cx.property}: animation"))
    note = "" if rr.reproduced else "the replay did not reproduce the violation"
    return tags, note


def _lattice_picture(name: str, tmp: str) -> str:
    from swarmproof.checkers.lattice_check import check_lattice, plot_lattice_check
    from swarmproof.models import library

    g = library.load(name)
    path = plot_lattice_check(g, check_lattice(g), os.path.join(tmp, f"lattice-{len(os.listdir(tmp))}.png"))
    with open(path, "rb") as fh:
        return _img(fh.read(), "image/png", f"lattice {name}")


def render_html(report, *, pictures: bool = True) -> str:
    """The page as text (``pictures=False`` leaves out the replays and lattice drawings)."""
    from swarmproof.checkers.ci_outputs import row_status, row_steps, summary_line

    summary = summary_line(report)
    cls = {0: "pass", 1: "fail", 3: "inconclusive"}.get(report.exit_code, "fail")
    out = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
           f'<meta http-equiv="Content-Security-Policy" content="{CSP}">',
           "<title>swarmproof verify</title>", f"<style>{_STYLE}</style>", "</head>", "<body>",
           "<h1>swarmproof verify</h1>", f'<p class="summary {cls}" id="summary">{_txt(summary)}</p>']
    if report.comparison is not None:
        b = report.comparison.baseline
        made = ", ".join(f"{k} {v}" for k, v in sorted(b.made_by.items()))
        out.append(f"<p>Baseline: <code>{_esc(b.path)}</code> (made with {_esc(made)})</p>")
    out += ['<h2>Property matrix</h2>', '<table id="matrix">',
            "<thead><tr><th>section</th><th>subject</th><th>property</th><th>verdict</th><th>status</th>"
            "<th>claim</th><th>detail</th></tr></thead>", "<tbody>"]
    details = []
    for i, r in enumerate(report.rows):
        kind, message = row_status(report, r)
        link = ""
        if r.verdict is Verdict.VIOLATED:
            link = f' <a href="#cx-{i}">counterexample</a>'
            details.append((i, r))
        elif r.section == "lattices":
            details.append((i, r))
        if not r.applicable:
            kind_class = f"{kind} na"
        else:
            kind_class = kind
        out.append(f'<tr class="row {kind_class}" data-verdict="{r.verdict.value}"><td>{_esc(r.section)}</td>'
                   f"<td>{_esc(r.subject)}</td><td>{_esc(r.property)}</td><td>{r.verdict.value}</td>"
                   f'<td class="status">{kind}: {_txt(message)}</td><td>{_txt(r.claim or "not claimed")}</td>'
                   f"<td>{_txt(r.detail)}{link}</td></tr>")
    out += ["</tbody>", "</table>"]
    with tempfile.TemporaryDirectory(prefix="swarmproof-html-") as tmp:
        violated = [(i, r) for i, r in details if r.verdict is Verdict.VIOLATED]
        if violated:
            out.append("<h2>Counterexamples</h2>")
        for i, r in violated:
            out.append(f'<div class="cx" id="cx-{i}"><h3>{_esc(r.subject)} / {_esc(r.property)}: violated</h3>')
            out.append(f"<p>{_txt(r.detail)}</p>")
            steps = row_steps(r)
            if steps:
                out.append("<pre>" + _txt("\n".join(steps)) + "</pre>")
            if pictures and r.artifact is not None:
                tags, note = _replay_pictures(r.artifact, tmp, f"cx-{i}")
                out.append('<div class="pictures">' + "".join(tags) + "</div>")
                if note:
                    out.append(f"<p>{_esc(note)}</p>")
            out.append("</div>")
        lattices = [(i, r) for i, r in details if r.section == "lattices"]
        if lattices:
            out.append("<h2>Lattices</h2>")
        for i, r in lattices:
            out.append(f'<div class="lattice" id="lattice-{i}"><h3>{_esc(r.subject)}: {r.verdict.value}</h3>'
                       f"<p>{_txt(r.detail)}</p>")
            if pictures:
                try:
                    out.append('<div class="pictures">' + _lattice_picture(r.subject, tmp) + "</div>")
                except Exception as exc:  # noqa: BLE001 - a drawing failure must not lose the report
                    out.append(f"<p>could not draw it: {_esc(type(exc).__name__)}: {_esc(exc)}</p>")
            out.append("</div>")
    out += ["</body>", "</html>", ""]
    return "\n".join(out)


def write_html(report, path) -> str:
    """Write :func:`render_html` atomically."""
    from swarmproof.models.fileio import atomic_write_text

    return atomic_write_text(path, render_html(report))
