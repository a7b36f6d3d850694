"""`rotorcontact reproduce`: every file is written and valid, the report is complete, and it renders in a browser."""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import xml.etree.ElementTree as ET
from html.parser import HTMLParser
from pathlib import Path

import matplotlib.image as mpimg
import numpy as np
import pytest

from rotorcontact.continuation.branches import orbit_branches
from rotorcontact.continuation.codim2 import codim2_diagram
from rotorcontact.plotting.branches import EVENT_NAMES
from rotorcontact.report.reproduce import (
    _ROWS,
    PAPER_VIEWS,
    WIDE,
    Reproduction,
    _fig2,
    _fig5,
    _fig6,
    _fig7,
    paper_parameters,
    paper_values,
    reproduce,
)

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


def test_the_captions_state_the_papers_findings_at_its_parameters(reproduction):
    _out, rep = reproduction
    captions = {name: caption for name, caption, _png, _svg in rep.figures}
    assert "B1,d near grazing at γ = 0.065" in captions["fig2_orbits"]
    # the paper's Fig. 3: a non-smooth fold at its omega, persistence at omega = 1
    assert f"(a) a non-smooth fold with x_P1 at ω = {rep.params.omega:g}" in captions["fig3_equilibria"]
    assert "(b) persistence of x_P2 into x_R at ω = 1." in captions["fig3_equilibria"]
    assert "γ_F,1..3" in captions["fig4_f1"]


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
    assert json.loads((tmp_path / "report.json").read_text())["paper"] == {}


# what the paper states beyond gamma*, gamma_F,1 and the persistence, under the report's keys
PAPER_STATES = {
    "B1d_grazing": "0.0636",
    "B1d_stability.gamma": "0.0834",
    "B1d_extrema_change": "0.0785",
    "ac_coalescence": "-0.497",
    "codim2_fold_dib.gamma": "0.178",
    "codim2_fold_dib.omega": "0.781",
}


def _resolve(report, key):
    """The value of a dotted key of the report (an index for lists); KeyError where there is none."""
    value = report
    for part in key.split("."):
        if isinstance(value, list):
            value = value[int(part)]
        elif isinstance(value, dict):
            value = value[part]
        else:
            raise KeyError(key)
    return value


def test_report_json_holds_every_stated_value_of_the_paper_under_the_reports_keys(reproduction):
    out, rep = reproduction
    report = json.loads((out / "report.json").read_text())
    stated = report["paper"]
    assert stated == paper_values()["values"]
    for key, value in PAPER_STATES.items():
        assert stated[key] == value, key
    for key, value in stated.items():
        assert isinstance(value, str), key
        assert key.split(".")[0] not in ("paper", "timings", "version"), key
        ours = _resolve(report, key)  # every key of "paper" is a key of the report
        assert isinstance(ours, (int, float)), (key, ours)
    rows = {q.key: q for q in rep.quantities}
    for key in PAPER_STATES:
        assert rows[key].paper == PAPER_STATES[key]
        assert rows[key].agrees, (key, rows[key].ours, rows[key].paper)
        assert "no value from the paper" not in rows[key].note


class _Tables(HTMLParser):
    """The cells of each row of each table of a page, by table id, as text."""

    def __init__(self):
        super().__init__()
        self.tables, self._table, self._row, self._cell = {}, None, None, None

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self._table = self.tables.setdefault(dict(attrs).get("id"), [])
        elif tag == "tr" and self._table is not None:
            self._row = []
            self._table.append(self._row)
        elif tag in ("td", "th") and self._row is not None:
            self._cell = ""

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self._row.append(self._cell)
            self._cell = None
        elif tag == "table":
            self._table = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data


def test_report_html_shows_the_papers_values_beside_ours(reproduction):
    out, rep = reproduction
    report = json.loads((out / "report.json").read_text())
    parser = _Tables()
    parser.feed((out / "report.html").read_text())
    results = {row[1]: row for row in parser.tables["results"] if len(row) == 6 and row[0] != "quantity"}
    shown = 0
    for key, value in report["paper"].items():
        if key in results:
            _label, _key, paper, ours, agrees, _note = results[key]
            assert paper == value and ours == f"{_resolve(report, key):.6g}" and agrees == "yes", results[key]
            shown += 1
    assert shown == len([k for k in report["paper"] if not k.startswith("parameters.")])
    params = {row[0]: row for row in parser.tables["parameters"]}
    for key, value in report["paper"].items():
        if key.startswith("parameters."):
            name = key.split(".", 1)[1]
            assert params[name][1] == value and params[name][2] == f"{report['parameters'][name]:.12g}"


def test_report_html_writes_math_labels_with_subscripts(reproduction):
    out, _rep = reproduction
    page = (out / "report.html").read_text()
    text = re.sub(r"data:image/png;base64,[A-Za-z0-9+/=]*", "", page)
    text = re.sub(r"<code>.*?</code>", "", text)  # report.json keys are shown as they are
    for raw in ("x_R", "x_P", "γ_F", "γ_DIB", "T_0", "F_1", "e_c"):
        assert raw not in text, raw
    assert re.search(r"\bB\d+,[a-d]", text) is None  # orbit labels as B<sub>1,a</sub>
    for html_label in ("x<sub>R</sub>", "γ<sub>F,1</sub>", "γ<sub>DIB</sub>", "B<sub>1,a</sub>", "B<sub>1,d</sub>"):
        assert html_label in text, html_label


@pytest.fixture(scope="module")
def paper_run(tmp_path_factory):
    """The branches and the two-parameter diagram of `reproduce`, to draw its figures again and inspect them."""
    p = paper_parameters()
    branches = orbit_branches(p, "gamma", *WIDE)
    diagram = codim2_diagram(p, ("gamma", "omega"), None, folds=(1,), grazing=())
    return p, branches, diagram, tmp_path_factory.mktemp("figures")


def _legend_texts(ax):
    legend = ax.get_legend()
    return [] if legend is None else [t.get_text() for t in legend.texts]


def test_figures_5_6b_and_7_are_drawn_at_the_papers_ranges(paper_run):
    p, branches, diagram, out = paper_run
    rep = Reproduction(p, True)
    axes5 = _fig5(p, rep, out, branches).axes
    assert PAPER_VIEWS["fig5b"][0] == PAPER_VIEWS["fig5d"][0] == (0.0, 0.2)
    assert axes5[1].get_xlim() == pytest.approx((0.0, 0.2)) and axes5[3].get_xlim() == pytest.approx((0.0, 0.2))
    axes6 = _fig6(p, rep, out, branches, diagram).axes
    assert axes6[1].get_xlim() == pytest.approx((0.0, 0.2))
    assert axes6[1].get_ylim() == pytest.approx((0.5, 3.0))
    assert axes6[1].get_yscale() == "linear"
    assert axes6[2].get_xlim() == pytest.approx(WIDE) and axes6[2].get_yscale() == "log"  # the wide view
    axes7 = _fig7(p, rep, out, branches).axes
    assert axes7[0].get_xlim() == pytest.approx((0.0, 0.2)) and axes7[0].get_ylim() == pytest.approx((0.96, 1.02))
    assert axes7[1].get_xlim() == pytest.approx((0.0, 0.2)) and axes7[1].get_ylim() == pytest.approx((-0.2, 1.4))
    # what the ranges are for: the NSFH, the grazing, the extrema change and the stability change of B1,d in view
    marks7b = {ln.get_gid(): ln for ln in axes7[1].get_lines() if (ln.get_gid() or "").startswith(("event:", "nsfh"))}
    assert {"nsfh", "event:grazing", "event:extrema-change"} <= set(marks7b)
    for ln in marks7b.values():
        assert 0.0 < ln.get_xdata()[0] < 0.2
    pd = [ln for ln in axes6[1].get_lines() if ln.get_gid() == "event:period-doubling"]
    assert pd and all(0.0 < ln.get_xdata()[0] < 0.2 and 0.5 < ln.get_ydata()[0] < 3.0 for ln in pd)
    # every kind of event marked has its legend entry (in (b) and (c), one legend in the fourth slot)
    for ax in (axes5[0], axes5[1], axes5[3]):
        kinds = {ln.get_gid().split(":")[1] for ln in ax.get_lines() if (ln.get_gid() or "").startswith("event:")}
        assert {"fold", "nsfh"} <= kinds
        assert {EVENT_NAMES[k] for k in kinds} <= set(_legend_texts(ax))
    # the two local estimates have an entry each
    assert sum(text.startswith("local estimate") for text in _legend_texts(axes5[1])) == 2
    assert {"NSFH", "fold", "period doubling", "grazing"} <= set(_legend_texts(axes6[3]))
    assert {"grazing", "change in number of extrema"} <= set(_legend_texts(axes7[1]))
    assert r"$x_R$" in _legend_texts(axes7[0])


def test_figure_2c_zooms_on_the_small_orbit(paper_run):
    p, _branches, _diagram, out = paper_run
    fig = _fig2(p, Reproduction(p, True), out)
    corotating = fig.axes[7]  # row (c), middle column
    (orbit,) = [ln for ln in corotating.get_lines() if ln.get_gid() == "orbit"]
    x, y = orbit.get_data()
    extent = max(np.ptp(x), np.ptp(y))
    lo, hi = corotating.get_xlim()
    assert extent < 0.01 * (hi - lo)  # too small to see at the scale of the clearance circle
    (zoom,) = [child for child in corotating.child_axes if child.get_label() == "zoom"]
    (zx0, zx1), (zy0, zy1) = zoom.get_xlim(), zoom.get_ylim()
    assert zx0 <= x.min() and x.max() <= zx1 and zy0 <= y.min() and y.max() <= zy1
    assert extent > 0.5 * (zx1 - zx0)  # it fills the inset
    assert r"$x_R$" in _legend_texts(corotating)


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
        # the page embeds its figures (megabytes of base64); on a loaded machine the driver can hand it back
        # before the document has been parsed to its end, so wait (boundedly) for the whole document
        from selenium.webdriver.support.ui import WebDriverWait

        WebDriverWait(browser, 60).until(
            lambda b: b.execute_script("return document.readyState") == "complete"
            and b.execute_script("return document.images.length") >= len(rep.figures)
        )
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
    for change in (dict(omega=1.0), dict(rho=0.05), dict(omega=0.8)):
        out = tmp_path / "_".join(f"{k}{v}" for k, v in change.items())
        rep = reproduce(out, paper_parameters().replace(**change), progress=False)
        assert len(rep.figures) == 6 and (out / "report.json").is_file() and (out / "report.html").is_file()
        # no gamma*, or one beyond Fig. 5's zoom (0.43 at omega = 1, 0.23 at 0.8): no local estimate is drawn,
        # and Fig. 5 does not claim one
        captions = {name: caption for name, caption, _png, _svg in rep.figures}
        assert "local estimate" not in captions["fig5_branches"]
        # the paper's findings are not claimed at other parameters
        assert "near grazing at γ = 0.065" not in captions["fig2_orbits"]
        assert "paper's values of γ" in captions["fig2_orbits"]
        assert "γ_F,1..3" not in captions["fig4_f1"] and "γ_F found there" in captions["fig4_f1"]
        if change == dict(omega=1.0):  # the paper's Fig. 3(b): persistence at omega = 1
            assert "(a) persistence of x_P2 into x_R at ω = 1;" in captions["fig3_equilibria"]


def test_reproduce_refuses_what_are_not_parameters_before_it_makes_the_folder(tmp_path):
    from rotorcontact import ParameterError, reference_machine
    from rotorcontact.report.reproduce import reproduce

    out = tmp_path / "new"
    for kw, name in ((dict(params=reference_machine()), "params"), (dict(params="gamma=0.1"), "params"),
                     (dict(progress="no"), "progress")):
        with pytest.raises(ParameterError, match=rf"^{name} = "):
            reproduce(out, **kw)
        assert not out.exists()
