"""The check that a Dataset is a given study's result, shared by the figures and the readers of results."""

from __future__ import annotations

import pytest
import xarray as xr

from rotorcontact import ParameterError
from rotorcontact.studies.datasets import check_dataset, study_dataset


def test_check_dataset_names_the_study_and_what_is_missing():
    ds = xr.Dataset({"a": ("x", [1.0])}, coords={"x": [0.0]}, attrs={"kind": "k"})
    assert check_dataset(ds, ("a", "x"), "some.study", attrs=("kind",)) is ds
    with pytest.raises(ParameterError, match=r"^ds = None is not an? Dataset object; allowed: a some\.study "
                                             r"result or its Dataset$"):
        check_dataset(None, ("a",), "some.study")
    with pytest.raises(ParameterError, match=r"^ds = <xarray\.Dataset> .* is not a result of some\.study; "
                                             r"allowed: a some\.study result or its Dataset \(it needs variables "
                                             r"'a', 'b' and attributes 'kind', 'other'; this one lacks variable "
                                             r"'b', attribute 'other'\)$"):
        check_dataset(ds, ("a", "b"), "some.study", attrs=("kind", "other"))


def test_study_dataset_takes_a_result_or_its_dataset():
    class Result:
        def __init__(self, dataset):
            self.dataset = dataset

    ds = xr.Dataset({"a": ("x", [1.0])})
    assert study_dataset(ds) is ds
    assert study_dataset(Result(ds)) is ds
    other = Result("not a dataset")
    assert study_dataset(other) is other  # left for check_dataset to refuse
