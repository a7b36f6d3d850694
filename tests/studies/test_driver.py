"""The chunked-study driver's refusals (the studies built on it are tested through their own modules)."""

from __future__ import annotations

import pytest

from rotorcontact import ParameterError
from rotorcontact.studies.driver import run_study


def _ok(**change):
    kw = dict(manifest={"study": "test"}, digest="abc", keys=lambda size: [], waves=lambda size, sink: [],
              assemble=lambda size, load: (None, 0), n_items=0, desc="test", chunk_size=1, progress=False)
    kw.update(change)
    return kw


@pytest.mark.parametrize("change, words", [
    ({"manifest": None}, "manifest = None"),
    ({"digest": 3}, "digest = 3"),
    ({"keys": None}, "keys = None"),
    ({"waves": None}, "waves = None"),
    ({"assemble": "x"}, "assemble = 'x'"),
    ({"n_items": -1}, "n_items"),
    ({"desc": None}, "desc = None"),
    ({"chunk_size": 0}, "chunk_size"),
    ({"fit_chunks": "yes"}, "fit_chunks"),
])
def test_run_study_refuses_each_argument_by_name(change, words):
    with pytest.raises(ParameterError, match=words):
        run_study(**_ok(**change))
