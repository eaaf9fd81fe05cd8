"""segment_motions reports its stages through the logging module."""

# SPDX-License-Identifier: BSD-3-Clause

import logging
import re

from sklearn_gpca import segment_motions


def test_stages_are_logged_at_info_level(lab_scene, caplog):
    tracks, _ = lab_scene
    with caplog.at_level(logging.INFO, logger="sklearn_gpca"):
        _, info = segment_motions(tracks, 2, random_state=0, return_info=True)
    messages = [record.getMessage() for record in caplog.records]
    assert all(record.name.startswith("sklearn_gpca.") for record in caplog.records)
    set_aside = int(info.outliers.sum())
    assert f"outlier screening: {set_aside} of 150 tracks set aside" in messages
    kept = 150 - set_aside
    drawn = [m for m in messages if m.startswith(f"{kept} tracks: 3 candidates drawn")]
    assert drawn and "(gpca, fragments, votes)" in drawn[0]
    refined = f"{kept} tracks: 9 refined candidates in "
    assert any(m.startswith(refined) for m in messages)
    judged = [m for m in messages if "candidates judged" in m]
    assert len(judged) == 1
    assert judged[0].endswith(f"kept {info.candidates[info.chosen]!r}")


def test_nothing_is_logged_at_the_default_level(lab_scene, caplog):
    tracks, _ = lab_scene
    with caplog.at_level(logging.WARNING, logger="sklearn_gpca"):
        segment_motions(tracks, 2, random_state=0)
    assert caplog.records == []


def _without_times(messages):
    return [re.sub(r"in \d+\.\d s", "in _ s", message) for message in messages]


def test_worker_processes_report_their_stages(lab_scene, caplog):
    tracks, _ = lab_scene
    runs = []
    for n_jobs in (1, 2):
        caplog.clear()
        with caplog.at_level(logging.INFO, logger="sklearn_gpca"):
            segment_motions(tracks, 2, random_state=0, n_jobs=n_jobs)
        runs.append(_without_times(record.getMessage() for record in caplog.records))
    # the pooled candidates are drawn in two worker processes with two jobs
    assert len(runs[0]) == 6
    assert runs[1] == runs[0]
