"""``limit report SCENE.json -o DIR`` on scenes outside the catalog: the page shows the alphas
(checked against closed forms), the interactive mechanism view, and renders in a real browser
(Debian's headless Chromium, installed by scripts/bootstrap.sh) without script errors."""
import json
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

from scenes import builders as B

ROOT = __import__("pathlib").Path(__file__).resolve().parent.parent


def _report(tmp_path, scene: dict, *extra) -> tuple[subprocess.CompletedProcess, object]:
    path = tmp_path / f"{scene['name']}.json"
    path.write_text(json.dumps(scene))
    out = tmp_path / "out"
    p = subprocess.run([sys.executable, "-m", "limit", "report", str(path), "-o", str(out), "--cache",
                        str(tmp_path / "cache"), "--no-progress", "--jobs", "2", *extra],
                       capture_output=True, text=True, cwd=ROOT, timeout=1800)
    return p, out


@pytest.fixture(scope="module")
def block2d(tmp_path_factory):
    """A 0.3 x 1.0 m block on a fixed base, mu 0.6, live load along +x: it overturns about its
    toe when alpha W (h/2) = W (b/2), so alpha = b/h = 0.3 (sliding needs mu = 0.6, higher)."""
    tmp = tmp_path_factory.mktemp("report2d")
    return _report(tmp, B.single_block(dim=2, b=0.3, h=1.0, mu=0.6, name="my-block-2d"), "--dem", "none")


@pytest.fixture(scope="module")
def wall3d(tmp_path_factory):
    """A 3D portal outside the catalog (no DEM): the page of a 3D scene."""
    tmp = tmp_path_factory.mktemp("report3d")
    return _report(tmp, B.portal(dim=3, t=0.4, name="my-portal-3d"), "--dem", "none")


@pytest.mark.slow  # limit report end to end
def test_report_writes_the_page_with_the_closed_form_alpha(block2d):
    p, out = block2d
    assert p.returncode == 0, p.stderr
    page = (out / "my-block-2d.html").read_text()
    # LP and step 2 both at the closed form b/h = 0.3, in the summary the page opens with
    assert re.search(r"Associative LP \(step 1, an upper bound\): alpha = 0\.3 \(optimal", page)
    assert re.search(r"Frictional limit analysis \(step 2, the answer\): alpha = 0\.3 \(", page)
    assert "alpha = 0.3" in p.stderr  # the same lines on the terminal
    for f in ("my-block-2d.md", "results.csv", "figures/my-block-2d.png", "vtk/my-block-2d.vtk"):
        assert (out / f).exists(), f
    # the interactive view, offline: plotly's script inlined, nothing fetched from a server
    assert page.count("plotly-graph-div") >= 1 and "Plotly.newPlot" in page
    assert not re.search(r"<script[^>]+src=['\"]https?:", page)
    assert (out / "my-block-2d.html").stat().st_size > 3e6  # the inlined script (about 4.6 MB)


@pytest.mark.slow  # limit report end to end
def test_report_reruns_from_the_cache(block2d, tmp_path):
    """An unchanged scene is not recomputed: the second run finds every stage in the cache."""
    p, out = block2d
    cache = out.parent / "cache"
    scene = out.parent / "my-block-2d.json"
    q = subprocess.run([sys.executable, "-m", "limit", "report", str(scene), "-o", str(tmp_path / "again"),
                        "--cache", str(cache), "--no-progress", "--dem", "none"], capture_output=True, text=True,
                       cwd=ROOT, timeout=600)
    assert q.returncode == 0, q.stderr
    assert "3 stage results cached, 0 to run" in q.stderr


@pytest.mark.slow  # limit report end to end
def test_report_of_a_glued_block_shows_the_certified_interval(tmp_path):
    """A 1.0 x 0.5 m block on a joint with mu 0.3 and c = 2,000 Pa (A = 1 m^2, W = 9,810 N):
    step 2 slides at mu + c A / W = 0.503874, the Radenkovic bound (friction removed, cohesion
    kept) at c A / W = 0.203874 (tests/test_cohesion.py derives both)."""
    d = B.single_block(dim=2, b=1.0, h=0.5, mu=0.3, name="glued-2d")
    d["joints"] = [{"between": {"blocks": ["base", "block"]}, "cohesion": 2000.0}]
    p, out = _report(tmp_path, d, "--dem", "none")
    assert p.returncode == 0, p.stderr
    page = (out / "glued-2d.html").read_text()
    assert "Lower bound with cohesion (Radenkovic: friction removed, cohesion kept): alpha = 0.203874; " \
           "the frictional minimum lies in [0.203874, 0.503874]." in page


@pytest.mark.slow  # about 2-4 s: limit report in a subprocess
def test_rejected_scene_is_one_line_exit_2(tmp_path):
    bad = B.single_block(dim=2, name="bad")
    bad["blocks"][1]["vertices"] = [[0, 0], [1, 0]]
    p, _ = _report(tmp_path, bad, "--dem", "none")
    assert p.returncode == 2 and p.stderr.count("\n") == 1 and p.stderr.startswith("error:")


@pytest.mark.slow  # about 2.5 s: limit report in a subprocess
def test_sweep_on_a_2d_scene_is_rejected(tmp_path):
    p, _ = _report(tmp_path, B.single_block(dim=2, name="flat"), "--dem", "none", "--sweep")
    assert p.returncode == 2 and "--sweep" in p.stderr


def _browser():
    exe = shutil.which("chromium")
    assert exe, "chromium is not installed: scripts/bootstrap.sh installs Debian's chromium"
    return exe


def _open(html_path, tmp_path, shot):
    """(DOM after the scripts ran, screenshot as an RGB array) of the page in headless Chromium,
    with a listener that writes any script error into the title."""
    page = html_path.read_text()
    probe = ("<script>window.addEventListener('error', function (e) { document.title = 'SCRIPT ERROR: ' + "
             "e.message; });</script>")
    copy = html_path.parent / f"probe-{html_path.name}"
    copy.write_text(page.replace("<head>", "<head>" + probe, 1))
    flags = [_browser(), "--headless", "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader",
             "--enable-unsafe-swiftshader", "--window-size=1200,1600", "--virtual-time-budget=8000"]
    dom = subprocess.run(flags + ["--dump-dom", copy.as_uri()], capture_output=True, text=True, timeout=180).stdout
    subprocess.run(flags + [f"--screenshot={shot}", copy.as_uri()], capture_output=True, text=True, timeout=180)
    import matplotlib.image as mpimg

    return dom, mpimg.imread(shot)[..., :3]


def _coloured(img) -> float:
    """Fraction of pixels that are neither grey nor white: the blocks coloured by their motion."""
    spread = img.max(axis=2) - img.min(axis=2)
    return float((spread > 0.25).mean())


@pytest.mark.slow  # limit report end to end
@pytest.mark.parametrize("which", ["block2d", "wall3d"])
def test_page_renders_in_a_real_browser(which, request, tmp_path):
    """The view draws: no script error, plotly's SVG (2D) or WebGL canvas (3D) in the DOM, and
    coloured blocks on the screenshot (a page whose script failed shows none)."""
    p, out = request.getfixturevalue(which)
    assert p.returncode == 0, p.stderr
    html_path = next(f for f in out.glob("*.html") if not f.name.startswith("probe-"))
    dom, img = _open(html_path, tmp_path, tmp_path / "shot.png")
    title = re.search(r"<title>(.*?)</title>", dom, re.S)
    assert title and "SCRIPT ERROR" not in title.group(1), title and title.group(1)
    assert "main-svg" in dom  # plotly drew its figure
    if which == "wall3d":
        assert "<canvas" in dom and "gl-container" in dom
    assert _coloured(img) > 0.002, "no coloured blocks on the screenshot"


@pytest.mark.slow  # limit report end to end
def test_the_check_above_fails_on_a_broken_page(block2d, tmp_path):
    """The browser test can fail: the same page with plotly's script removed raises a script
    error and draws nothing."""
    _, out = block2d
    page = (out / "my-block-2d.html").read_text()
    broken = tmp_path / "broken.html"
    start = page.index("<script")
    end = page.index("</script>", start) + len("</script>")
    broken.write_text(page[:start] + page[end:])
    dom, img = _open(broken, tmp_path, tmp_path / "shot.png")
    assert "SCRIPT ERROR" in re.search(r"<title>(.*?)</title>", dom, re.S).group(1)
    assert "main-svg" not in dom and _coloured(img) < 0.002


@pytest.mark.slow
@pytest.mark.yade
@pytest.mark.lmgc90
def test_report_with_both_engines_3d(tmp_path):
    """A 3D block 0.3 x 0.4 x 1.0 m (b along the load), mu 0.6, outside the catalog, with YADE and
    LMGC90: both engines collapse near the closed form b/h = 0.3 (rocking about the toe; the
    friction cone does not bind, mu > 0.3), inside the bracket, and the page shows their alphas
    and their motions beside the limit analysis's."""
    scene = B.single_block(dim=3, b=0.3, h=1.0, t=0.4, mu=0.6, name="my-block-3d")
    p, out = _report(tmp_path, scene, "--dem", "both")
    assert p.returncode == 0, p.stderr
    page = (out / "my-block-3d.html").read_text()
    for engine in ("YADE", "LMGC90"):
        m = re.search(engine + r": collapses at alpha = ([0-9.]+)", page)  # in the summary
        assert m, engine
        assert float(m.group(1)) == pytest.approx(0.3, rel=0.03)
        assert f"{engine} at collapse" in page  # its motion in the interactive view
    summary = re.search(r'<div class="summary">(.*?)</div>', page, re.S).group(1)
    assert summary.count("inside the bracket") == 2 and "suspect" not in summary
    df = __import__("pandas").read_csv(out / "results.csv")
    assert np.isfinite(df.dem_alpha[0]) and np.isfinite(df.lmgc_alpha[0])
