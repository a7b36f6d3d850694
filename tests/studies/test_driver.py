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


class _Ones:
    """A task of another kind (`rotorcontact.studies.execution.run_task`): a block of ones under its key."""

    def __init__(self, key: str) -> None:
        self.key, self.n_items = key, 1

    def compute(self, parallel: bool) -> dict:
        import numpy as np

        return {"summary": np.ones(8)}


def test_chunks_held_in_memory_are_let_go_as_they_are_assembled():
    """Without an output file the chunks are held in memory until the study is assembled; each is let go as it
    is loaded, so the study is never held twice."""
    keys = [f"c{i}" for i in range(5)]
    seen = {}

    def waves(size, sink):
        seen["sink"] = sink
        yield [_Ones(k) for k in keys]

    def assemble(size, load):
        for i, k in enumerate(keys):
            assert load(k)["summary"].sum() == 8.0
            assert len(seen["sink"]) == len(keys) - i - 1
        import xarray as xr

        return xr.Dataset(), 0

    run_study(**_ok(keys=lambda size: keys, waves=waves, assemble=assemble, n_items=5))
    assert len(seen["sink"]) == 0
