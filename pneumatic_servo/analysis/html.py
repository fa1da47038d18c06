"""The building blocks of the HTML reports: one self-contained page, PNGs embedded."""
from __future__ import annotations

import base64
import html
from pathlib import Path

import numpy as np

CSS = ('body{font-family:sans-serif;max-width:1200px;margin:2em auto;color:#222}'
       'table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;'
       'padding:3px 8px;font-size:13px;text-align:right}th{background:#eee}'
       'td.l,th.l{text-align:left}img{max-width:100%;border:1px solid #ddd;margin:4px 0}'
       '.status{font-size:1.2em;padding:0.6em;margin:0.5em 0;border:2px solid}'
       '.ok{background:#eef6ee;border-color:#5a5}.warn{background:#fff6e0;border-color:#d90}'
       '.bad{background:#fde8e8;border-color:#c33}.worse{color:#c33;font-weight:bold}'
       '.note{color:#555;font-size:13px}')


def img(out_dir: Path, name: str, alt: str) -> str:
    """The PNG ``out_dir / name`` embedded, so that the page can be mailed on its own."""
    data = base64.b64encode((out_dir / name).read_bytes()).decode()
    return f'<p><img src="data:image/png;base64,{data}" alt="{html.escape(alt)}" ' \
           f'title="{html.escape(name)}"></p>'


def table(header: list[str], rows: list[list], left: int = 1, escape_header: bool = True,
          prose: tuple[int, ...] = ()) -> str:
    """A table of cells given as HTML; the first ``left`` columns, and those in ``prose``
    (sentences, which read badly right-aligned), are left-aligned. The header is escaped
    unless it holds HTML of its own (``escape_header=False``)."""
    def cell(tag: str, i: int, content) -> str:
        return f'<{tag} class="l">{content}</{tag}>' if i < left or i in prose else \
            f'<{tag}>{content}</{tag}>'
    head = [html.escape(h) if escape_header else h for h in header]
    out = ['<table><tr>' + ''.join(cell('th', i, h) for i, h in enumerate(head)) + '</tr>']
    for row in rows:
        out.append('<tr>' + ''.join(cell('td', i, c) for i, c in enumerate(row)) + '</tr>')
    return '\n'.join(out) + '</table>'


def fmt(v, digits=4) -> str:
    """A number with ``digits`` significant digits, '-' for none or not finite."""
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return '-'
    return f'{v:.{digits}g}' if isinstance(v, (float, np.floating)) else html.escape(str(v))


def page(title: str, body: list[str]) -> str:
    """The whole page: a title and the body's pieces."""
    return ('<!DOCTYPE html><html><head><meta charset="utf-8"><title>' + html.escape(title)
            + f'</title><style>{CSS}</style></head><body><h1>{html.escape(title)}</h1>\n'
            + '\n'.join(body) + '</body></html>\n')
