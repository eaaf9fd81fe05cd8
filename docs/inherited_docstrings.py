"""scikit-learn's text in the docstrings of inherited methods.

The estimators inherit ``fit_predict``, ``set_output``, ``get_params`` and
others from scikit-learn, whose docstrings note scikit-learn versions ("Added
in version 1.4") and point to sections of scikit-learn's user guide and
gallery, which mean nothing beside this package's version and pages.
:func:`clean_sklearn_docstrings` (an ``autodoc-process-docstring`` handler)
drops those notes and says where the method comes from.
"""

# SPDX-License-Identifier: BSD-3-Clause

import re

# A directive noting a scikit-learn version, and its indented body.
_VERSION_NOTE = re.compile(r"^(\s*)\.\. (versionadded|versionchanged|deprecated)::")


def _drop_version_notes(lines):
    kept, skip_indent = [], None
    for line in lines:
        if skip_indent is not None:
            indent = len(line) - len(line.lstrip())
            if not line.strip() or indent > skip_indent:
                continue
            skip_indent = None
        match = _VERSION_NOTE.match(line)
        if match:
            skip_indent = len(match.group(1))
            continue
        kept.append(line)
    return kept


# :ref:`text <label>` or :ref:`label` into scikit-learn's own pages.
_REF = re.compile(r":ref:`([^`<]*?)(\s*<[^>]*>)?`")


def _drop_refs(lines):
    """Drop the paragraphs that point into scikit-learn's user guide.

    An unindented paragraph (the description) with such a reference goes; in
    an indented one (a parameter's description) the reference becomes its
    text, or nothing when it has no text but a label.
    """
    kept, paragraph = [], []
    for line in [*lines, ""]:
        if line.strip():
            paragraph.append(line)
            continue
        if any(":ref:" in p for p in paragraph):
            if not paragraph[0].startswith(" "):
                paragraph = []
            paragraph = [
                _REF.sub(lambda m: m.group(1) if m.group(2) else "", p)
                for p in paragraph
            ]
        kept += paragraph
        if paragraph or (kept and kept[-1].strip()):
            kept.append(line)
        paragraph = []
    return kept[:-1] if kept and not kept[-1].strip() else kept


def clean_sklearn_docstrings(app, what, name, obj, options, lines):
    """Mark inherited scikit-learn methods as such, without version notes.

    Their docstrings note versions of scikit-learn ("Added in version 1.4")
    and point to sections of scikit-learn's user guide and gallery, which
    mean nothing next to this package's version and pages.
    """
    module = getattr(obj, "__module__", "") or ""
    if not module.startswith("sklearn.") or not lines:
        return
    lines[:] = _drop_refs(_drop_version_notes(lines))
    owner = getattr(obj, "__qualname__", "").rpartition(".")[0]
    if what == "method" and owner:
        end = lines.index("") if "" in lines else len(lines)
        lines[end:end] = ["", f"Inherited from scikit-learn's ``{owner}``."]
