"""`rotorcontact reproduce`: every file is written and valid, the report is complete, and it renders in a browser."""

from __future__ import annotations

import json
import math
import os
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import matplotlib.image as mpimg
import pytest

from rotorcontact.reproduce import _ROWS, paper_parameters, reproduce

REPORT_KEYS = (
    "nondimensional",
    "gamma_star",
    "gamma_F",
    "gamma_DIB",
    "B1d_grazing",
    "B1d_stability",
    "B1d_extrema_change",
    "ac_coalescence",
    "codim2_fold_dib",
    "persistence_gamma_star",
    "timings",
)


@pytest.fixture(scope="module")
def reproduction(tmp_path_factory):
    out = tmp_path_factory.mktemp("reproduction")
    rep = reproduce(out, progress=False)
    return out, rep


def _finite_leaves(value, path="report"):
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _finite_leaves(v, f"{path}.{k}")
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _finite_leaves(v, f"{path}[{i}]")
    else:
        yield path, value


def test_every_file_exists_and_is_a_valid_image(reproduction):
    out, rep = reproduction
    assert len(rep.figures) == 6
    for name, caption, png, svg in rep.figures:
        assert caption
        image = mpimg.imread(png)
        assert image.ndim == 3 and image.shape[0] > 200 and image.shape[1] > 200
        assert image.std() > 0.01  # not blank
        root = ET.parse(svg).getroot()
        assert root.tag.endswith("svg")
    assert (out / "report.html").stat().st_size > 10_000


def test_report_json_has_every_key_with_a_finite_value(reproduction):
    out, _rep = reproduction
    report = json.loads((out / "report.json").read_text())
    for key in REPORT_KEYS:
        assert key in report, key
    assert set(report["nondimensional"]) == {"gamma", "omega", "rho"}
    assert len(report["gamma_F"]) == 3
    assert set(report["B1d_stability"]) == {"gamma", "type"}
    assert set(report["codim2_fold_dib"]) == {"gamma", "omega"}
    for path, value in _finite_leaves({k: report[k] for k in REPORT_KEYS}):
        if path == "report.B1d_stability.type":
            assert value in ("branch-point", "period-doubling", "neimark-sacker"), value
        else:
            assert isinstance(value, (int, float)) and math.isfinite(value), (path, value)
    assert report["ac_coalescence"] < 0
    assert set(report["timings"]) >= {"branches", "figure 2"}


def test_paper_values_agree_where_the_paper_states_them(reproduction):
    """MODEL.md's stated values: gamma* ~ 0.072 (= gamma_DIB), gamma_F,1 ~ 0.178, gamma* = rho at omega = 1."""
    _out, rep = reproduction
    stated = [q for q in rep.quantities if q.paper is not None]
    assert {q.key for q in stated} >= {"gamma_star", "gamma_F.0", "gamma_DIB", "persistence_gamma_star"}
    for q in stated:
        assert q.agrees, (q.key, q.ours, q.paper)
    assert any(q.note == "not stated in the paper" for q in rep.quantities)


def test_other_parameters_leave_the_paper_column_empty(tmp_path):
    rep = reproduce(tmp_path, paper_parameters().replace(mu=0.2), progress=False)
    assert all(q.paper is None and q.agrees is None for q in rep.quantities)


def _browser_paths():
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    driver = shutil.which("chromedriver")
    return chromium, driver


def test_report_renders_in_headless_chromium(reproduction):
    chromium, driver_path = _browser_paths()
    if not (chromium and driver_path):
        if os.environ.get("RC_REQUIRE_BROWSER"):
            pytest.fail("chromium and chromedriver are required (RC_REQUIRE_BROWSER is set) but not found")
        pytest.skip("chromium / chromedriver not installed")
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    out, rep = reproduction
    opts = webdriver.ChromeOptions()
    opts.binary_location = chromium
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--no-first-run", "--window-size=1200,2000"):
        opts.add_argument(flag)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    browser = webdriver.Chrome(service=Service(driver_path), options=opts)
    try:
        browser.get((out / "report.html").resolve().as_uri())
        images = browser.execute_script(
            "return Array.from(document.images).map(i => [i.complete, i.naturalWidth]);"
        )
        assert len(images) == len(rep.figures)
        assert all(complete and width > 0 for complete, width in images), images
        rows = browser.execute_script("return document.querySelectorAll('#results tbody tr').length;")
        assert rows == len(_ROWS)
        errors = [e for e in browser.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]
        assert errors == []
        shot = Path(os.environ.get("RC_SCREENSHOT_DIR", out)) / "report_screenshot.png"
        shot.parent.mkdir(parents=True, exist_ok=True)
        assert browser.save_screenshot(str(shot))
        print(f"screenshot of the report: {shot}")
    finally:
        browser.quit()


def test_reproduce_finishes_where_some_panels_do_not_exist(tmp_path):
    """At omega = 1 x_R is virtual at gamma = 0.3 and at rho = 0.05 there is no boundary equilibrium:
    the run still writes every figure and a report, with those panels marked as not defined."""
    for change in (dict(omega=1.0), dict(rho=0.05)):
        out = tmp_path / "_".join(f"{k}{v}" for k, v in change.items())
        rep = reproduce(out, paper_parameters().replace(**change), progress=False)
        assert len(rep.figures) == 6 and (out / "report.json").is_file() and (out / "report.html").is_file()
