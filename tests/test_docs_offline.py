"""The documentation renders offline, and its tables and figures follow the results.

Fast checks on the sources; the documentation build itself runs in CI after
the tests (``.ci/run``).
"""

# SPDX-License-Identifier: BSD-3-Clause

import csv
import importlib.util
import inspect
import re
import zlib
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
DOCS = ROOT / "docs"
RESULTS = ROOT / "benchmarks" / "results"

# <script src="http..."> or <link href="http..."> (a script or style sheet
# loaded from another host); links to pages (<a href>) are fine.
EXTERNAL_ASSET = re.compile(
    r"<(script|link)\b[^>]*\b(src|href)\s*=\s*[\"']?(https?:)?//", re.IGNORECASE
)


def load(path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_external_asset_pattern():
    assert EXTERNAL_ASSET.search('<script src="https://cdn.example.org/x.js">')
    assert EXTERNAL_ASSET.search("<link rel=stylesheet href=//cdn.example.org/x.css>")
    assert not EXTERNAL_ASSET.search('<script src="../_static/mathjax/tex.js">')
    assert not EXTERNAL_ASSET.search('<a href="https://scikit-learn.org">')


def test_docs_sources_load_nothing_from_another_host():
    sources = [
        p
        for p in DOCS.rglob("*")
        if p.suffix in {".rst", ".html", ".py", ".css", ".js"}
        and "_build" not in p.parts
        and "auto_examples" not in p.parts
        and "gen_modules" not in p.parts
    ]
    assert sources
    offending = [p for p in sources if EXTERNAL_ASSET.search(p.read_text())]
    assert not offending, offending


def test_conf_serves_mathjax_and_writes_no_cdn_page():
    conf = (DOCS / "conf.py").read_text()
    # MathJax from the sphinx-mathjax-offline package, not the default CDN
    assert '"sphinx-mathjax-offline"' in conf
    assert "mathjax_path" not in conf
    # sphinx-gallery's execution-times page loads jQuery and DataTables from a CDN
    assert '"write_computation_times": False' in conf


@pytest.mark.skipif(
    not (DOCS / "_build" / "html" / "index.html").exists(),
    reason="documentation not built",
)
def test_built_pages_load_nothing_from_another_host():
    pages = list((DOCS / "_build" / "html").rglob("*.html"))
    pages = [p for p in pages if "_static" not in p.parts]
    offending = [p for p in pages if EXTERNAL_ASSET.search(p.read_text())]
    assert not offending, offending
    assert not any("Added in version" in p.read_text() for p in pages)


def test_csv_tables_match_the_markdown_pages(tmp_path):
    tables = load(ROOT / "benchmarks" / "_tables.py")
    pages = sorted(RESULTS.glob("*.md"))
    assert pages
    for page in pages:
        expected = tables.read_markdown_tables(page.read_text())
        paths = tables.table_paths(page, len(expected))
        for table, path in zip(expected, paths, strict=True):
            with path.open(newline="") as f:
                assert list(csv.reader(f)) == table, path
    # and write_markdown derives them
    page = tmp_path / "demo.md"
    text = "# T\n\n| a | b |\n|---|---|\n| 1 | x, y |\n\ntext\n\n| c |\n|---|\n| 2 |\n"
    written = tables.write_markdown(page, text)
    assert [p.name for p in written] == ["demo.csv", "demo_2.csv"]
    assert written[0].read_text() == 'a,b\n1,"x, y"\n'
    assert written[1].read_text() == "c\n2\n"


def test_result_figures_are_drawn_from_the_committed_results(tmp_path):
    pytest.importorskip("matplotlib")
    figures = load(DOCS / "make_result_figures.py")
    paths = figures.main(tmp_path)
    assert len(paths) >= 4
    for path in paths:
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", path


def test_offline_inventory_lists_sklearn_names_and_terms(tmp_path):
    inventories = load(DOCS / "offline_inventories.py")
    mapping = inventories.write_inventories(tmp_path)
    assert mapping["sklearn"][0] == "https://scikit-learn.org/stable"
    data = Path(mapping["sklearn"][1]).read_bytes()
    _, _, body = data.partition(b"zlib.\n")
    lines = zlib.decompress(body).decode().splitlines()
    entries = {line.split()[0]: line.split()[1:4] for line in lines}
    assert entries["sklearn.model_selection.GridSearchCV"] == [
        "py:class",
        "1",
        "modules/generated/sklearn.model_selection.GridSearchCV.html#"
        "sklearn.model_selection.GridSearchCV",
    ]
    assert entries["sklearn.impute.IterativeImputer"][0] == "py:class"
    assert entries["fit"][:1] == ["std:term"]
    assert (
        "numpy.linalg.svd"
        in zlib.decompress(
            Path(mapping["numpy"][1]).read_bytes().partition(b"zlib.\n")[2]
        ).decode()
    )


def test_inherited_docstrings_lose_sklearn_version_notes_and_guide_links():
    from sklearn.base import ClusterMixin
    from sklearn.utils._set_output import _SetOutputMixin

    docstrings = load(DOCS / "inherited_docstrings.py")
    for method in (_SetOutputMixin.set_output, ClusterMixin.fit_predict):
        lines = inspect.cleandoc(method.__doc__).splitlines()
        assert any("versionadded" in line for line in lines)
        docstrings.clean_sklearn_docstrings(None, "method", "", method, {}, lines)
        text = "\n".join(lines)
        assert "versionadded" not in text
        assert ":ref:" not in text
        assert "sphx_glr" not in text
        assert "Inherited from scikit-learn" in text
        assert "Parameters\n----------" in text


CONFLICT_MARKER = re.compile(r"^(<{7}|>{7})( |$)", re.MULTILINE)


def test_conflict_marker_pattern():
    assert CONFLICT_MARKER.search("text\n<<<<<<< HEAD\nmore")
    assert CONFLICT_MARKER.search(">>>>>>> main\n")
    assert not CONFLICT_MARKER.search("a <<<<<<< b\n========\n")


def test_no_merge_conflict_markers_left():
    """A merge conflict left in a page or a table must not ship."""
    suffixes = {".md", ".rst", ".py", ".toml", ".csv", ".txt"}
    dirs = [DOCS, ROOT / "benchmarks", ROOT / "sklearn_gpca", ROOT / "tests"]
    paths = [ROOT / "README.md"]
    paths += [p for d in dirs for p in d.rglob("*") if p.suffix in suffixes]
    left = [
        str(p.relative_to(ROOT))
        for p in paths
        if "_build" not in p.parts
        and CONFLICT_MARKER.search(p.read_text(encoding="utf-8", errors="replace"))
    ]
    assert left == []
