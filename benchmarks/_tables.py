"""Write a benchmark's Markdown result page and each of its tables as CSV.

Every benchmark script writes ``benchmarks/results/<name>.md`` through
:func:`write_markdown`, which also writes the page's Markdown tables to
``benchmarks/results/tables/<name>.csv`` (the first table) and
``<name>_2.csv``, ``<name>_3.csv``, ... (the next ones), cell for cell. The
documentation renders those CSV files as HTML tables and draws its figures
from them, so the Markdown page, the CSV tables and the figures cannot
disagree.

To re-derive the CSV tables of the committed pages without re-running a
benchmark::

    python benchmarks/_tables.py benchmarks/results/*.md
"""

# SPDX-License-Identifier: BSD-3-Clause

import csv
import datetime
import os
import shlex
import sys
from pathlib import Path

#: Folder of the CSV tables, beside the Markdown pages.
TABLES = "tables"


def markdown_table(header, rows):
    """Lines of a Markdown table; ``rows`` hold the cells as strings."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return lines


def command_stamp(command):
    """```command```, the UTC time and the BLAS threads, for a page's intro."""
    now = datetime.datetime.now(datetime.timezone.utc)
    threads = os.environ.get("OMP_NUM_THREADS", "the default")
    return f"`{command}`, {now:%d %b %Y %H:%M} UTC, BLAS threads: {threads}"


def command_line(script, args, options):
    """The command that reruns ``benchmarks/<script>`` with the parsed
    ``args``: each of ``options`` (dest names) as ``--option value...``,
    lists joined by spaces, floats as ``:g``, quoted for the shell where
    needed (a scene name with a space); ``--out`` last."""

    def text(value):
        return f"{value:g}" if isinstance(value, float) else shlex.quote(str(value))

    parts = [f"python benchmarks/{script}"]
    for option in (*options, "out"):
        value = getattr(args, option)
        values = value if isinstance(value, list | tuple) else [value]
        parts.append(f"--{option.replace('_', '-')} " + " ".join(map(text, values)))
    return " ".join(parts)


def write_check_page(path, command, doc, title, sections, *, stamp_note=""):
    """Write a check script's page: the command's stamp (with ``stamp_note``,
    e.g. ``", one job"``), the paragraph of ``doc`` after its title line as the
    intro, then the ``(heading, header, rows)`` sections; returns the CSVs."""
    intro = f"{command_stamp(command)}{stamp_note}. " + " ".join(
        doc.split("\n\n")[1].split()
    )
    return write_markdown(path, page_with_tables(title, intro, sections))


def page_with_tables(title, intro, sections):
    """A Markdown page: the title, the intro, then ``(heading, header, rows)``
    sections, each a table under its heading."""
    tables = [
        f"## {heading}\n\n" + "\n".join(markdown_table(header, rows))
        for heading, header, rows in sections
    ]
    return f"# {title}\n\n{intro}\n\n" + "\n\n".join(tables) + "\n"


def _split_row(line):
    cells = line.strip().removeprefix("|").removesuffix("|").split("|")
    return [cell.strip() for cell in cells]


def read_markdown_tables(text):
    """The tables of a Markdown page, each a list of rows (header first).

    A table is a block of lines starting with ``|`` whose second line is the
    ``|---|`` delimiter row.
    """
    tables, block = [], []
    for line in [*text.splitlines(), ""]:
        if line.lstrip().startswith("|"):
            block.append(line)
            continue
        if len(block) >= 2 and set(block[1].replace("|", "").strip()) <= set("-: "):
            tables.append([_split_row(block[0])] + [_split_row(b) for b in block[2:]])
        block = []
    return tables


def table_paths(markdown_path, count):
    """``tables/<name>.csv``, ``tables/<name>_2.csv``, ... beside the page."""
    markdown_path = Path(markdown_path)
    folder = markdown_path.parent / TABLES
    stem = markdown_path.stem
    return [
        folder / (f"{stem}.csv" if k == 1 else f"{stem}_{k}.csv")
        for k in range(1, count + 1)
    ]


def write_markdown(path, text):
    """Write the Markdown page ``path`` and its tables as CSV; return the CSVs."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return write_tables(path)


def write_tables(path):
    """Write the tables of the Markdown page ``path`` as CSV files."""
    path = Path(path)
    tables = read_markdown_tables(path.read_text())
    paths = table_paths(path, len(tables))
    stale = table_paths(path, 20)[len(tables) :]
    for old in stale:
        old.unlink(missing_ok=True)
    for table, target in zip(tables, paths, strict=True):
        target.parent.mkdir(parents=True, exist_ok=True)
        with target.open("w", newline="") as f:
            csv.writer(f, lineterminator="\n").writerows(table)
    return paths


if __name__ == "__main__":
    for name in sys.argv[1:]:
        for written in write_tables(name):
            print(written)
