"""``report.html`` opened in a real browser (headless Chromium through selenium).

The report of ``gearsim reproduce`` is built once at reduced size (no FE route, 13
revolutions, one sensitivity depth, one fault severity: ``small_reproduction`` of
tests/conftest.py) and loaded from its ``file://`` URL. The page must

* load with no SEVERE entry in the browser console log (script errors, failed loads);
* decode every figure: each ``<img>`` is ``complete``, has ``naturalWidth > 0`` and its
  ``decode()`` promise resolves;
* carry the report's title and its claims table;
* paint a non-blank first screen (see :func:`screenshot_problems` for the thresholds).

A second test feeds the same checks a copy of the report with one figure's base64
corrupted, a ``console.error`` injected and (separately) the body hidden, and asserts
that each defect is reported, so that the checks above are known to be able to fail.

The browser is Debian's ``chromium`` with its ``chromium-driver`` at fixed paths
(``/usr/bin/chromium``, ``/usr/bin/chromedriver``), installed by ``make browser``, on
which ``make test`` depends; selenium is given both paths, so Selenium Manager never
downloads anything. When they are missing the tests FAIL with a message to run
``make test``. They are skipped only when the environment variable
``GEARSIM_NO_BROWSER=1`` is set (an explicit opt-out, for machines without the
browser packages).
"""

from __future__ import annotations

import base64
import io
import os
import re
from pathlib import Path

import pytest

CHROMIUM = Path("/usr/bin/chromium")
CHROMEDRIVER = Path("/usr/bin/chromedriver")
TITLE = "gearsim reproduction of Shi, Li & Zhou (2025)"
N_FIGURES = 7  # fig3_stiffness, fig5_time, fig6_spectrum, fig7_zooms, fig8_stft, sensitivity,
#               fault magnitudes
WINDOW = (1280, 900)  # CSS px of the window; its viewport is the "first screen"
PAGE_LOAD_TIMEOUT = 60  # s: the report is a few MB of inline base64
SCRIPT_TIMEOUT = 30  # s: img.decode() of six PNGs
# A first screen counts as painted when it has more than MIN_COLOURS distinct colours and
# more than MIN_INK of its pixels are not (near) white. Measured with Debian's Chromium
# 156 (window 1280x900, viewport 1280x757): the report's first screen (title, run line,
# section 1, the head of the claims table) has 223 colours (anti-aliased text) and 17 %
# non-white pixels; a blank page, or the report with its body hidden, has 1 colour and
# 0 %. The thresholds sit an order of magnitude below the report and far above blank, so
# font or layout changes do not trip them but an empty or unpainted page does.
MIN_COLOURS = 32
MIN_INK = 0.02
NEAR_WHITE = 245  # all of R, G, B at or above this count as white

pytestmark = pytest.mark.skipif(os.environ.get("GEARSIM_NO_BROWSER") == "1",
                                reason="GEARSIM_NO_BROWSER=1: browser checks of the "
                                       "report explicitly disabled")


def _require_browser() -> None:
    missing = [str(p) for p in (CHROMIUM, CHROMEDRIVER) if not p.is_file()]
    if missing:
        pytest.fail(f"headless browser not installed ({', '.join(missing)} missing): run "
                    "`make test`, which installs Debian's chromium and chromium-driver "
                    "(`make browser`), or set GEARSIM_NO_BROWSER=1 to skip these checks",
                    pytrace=False)


@pytest.fixture(scope="module")
def report(small_reproduction) -> Path:
    """report.html of ``gearsim reproduce`` at reduced size (tests/conftest.py: built once
    per session, shared with the other tests that need a whole report)."""
    _require_browser()  # fail before spending the build time
    return small_reproduction / "report.html"


@pytest.fixture
def browser(tmp_path):
    """A fresh headless Chromium (own profile in tmp_path), quit at teardown."""
    _require_browser()
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = str(CHROMIUM)
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu",
                 "--disable-dev-shm-usage", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--hide-scrollbars",
                 f"--window-size={WINDOW[0]},{WINDOW[1]}",
                 f"--user-data-dir={tmp_path / 'chromium-profile'}"):
        opts.add_argument(flag)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    service = Service(executable_path=str(CHROMEDRIVER),
                      log_output=str(tmp_path / "chromedriver.log"))
    driver = webdriver.Chrome(service=service, options=opts)
    try:
        driver.set_page_load_timeout(PAGE_LOAD_TIMEOUT)
        driver.set_script_timeout(SCRIPT_TIMEOUT)
        yield driver
    finally:
        driver.quit()


# -- checks (each returns a list of problems; empty means the check passed) ------------

_IMAGES_JS = """
const done = arguments[arguments.length - 1];
const imgs = Array.from(document.images);
Promise.all(imgs.map((img, i) => img.decode().then(() => null, e => String(e))))
  .then(errs => done(imgs.map((img, i) => ({
      alt: img.alt || ('#' + i), complete: img.complete,
      width: img.naturalWidth, height: img.naturalHeight, decodeError: errs[i]}))));
"""


def load(driver, path: Path) -> None:
    """Open ``path`` and wait until the document and all its images have loaded."""
    from selenium.webdriver.support.ui import WebDriverWait

    driver.get(path.resolve().as_uri())
    WebDriverWait(driver, PAGE_LOAD_TIMEOUT).until(
        lambda d: d.execute_script("return document.readyState") == "complete")


def console_problems(driver) -> list[str]:
    """SEVERE entries of the browser console since the last call (the log is drained);
    inline base64 in the messages is cut to its first 16 characters."""
    return [f"console {e['level']}: "
            + re.sub(r"(base64,[A-Za-z0-9+/=!]{16})[A-Za-z0-9+/=!.]+", r"\1...", e["message"])
            for e in driver.get_log("browser") if e["level"] == "SEVERE"]


def image_problems(driver, expected: int | None = None) -> list[str]:
    """Every ``<img>``: complete, naturalWidth/Height > 0 and ``decode()`` resolves."""
    images = driver.execute_async_script(_IMAGES_JS)
    bad = [f"image {i['alt']}: complete={i['complete']} {i['width']}x{i['height']} "
           f"decode={i['decodeError'] or 'ok'}" for i in images
           if not (i["complete"] and i["width"] > 0 and i["height"] > 0)
           or i["decodeError"]]
    if expected is not None and len(images) != expected:
        bad.append(f"{len(images)} images in the page, expected {expected}")
    return bad


def content_problems(driver) -> list[str]:
    """The title and the claims table (section 2, a table with a 'seed' column)."""
    bad = []
    if driver.title != TITLE:
        bad.append(f"title {driver.title!r}, expected {TITLE!r}")
    has_claims = driver.execute_script("""
      const h = Array.from(document.querySelectorAll('h2'))
                     .find(e => e.textContent.includes('quantitative claims'));
      if (!h) return false;
      for (let e = h.nextElementSibling; e && e.tagName !== 'H2'; e = e.nextElementSibling) {
        const t = e.tagName === 'TABLE' ? e : e.querySelector('table');
        const head = t ? t.rows[0].textContent.toLowerCase() : '';
        if (t && t.rows.length > 1 && head.includes('claim') && head.includes('seed'))
          return true;
      }
      return false;""")
    if not has_claims:
        bad.append("no claims table (a table with 'claim' and 'seed' columns under the "
                   "'quantitative claims' heading)")
    return bad


def screenshot_problems(driver) -> list[str]:
    """The first screen is painted: > MIN_COLOURS colours, > MIN_INK non-white pixels."""
    import numpy as np
    from PIL import Image

    png = driver.get_screenshot_as_png()
    rgb = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).reshape(-1, 3)
    packed = (rgb[:, 0].astype(np.uint32) << 16) | (rgb[:, 1].astype(np.uint32) << 8) | rgb[:, 2]
    n_colours = np.unique(packed).size
    ink = float(np.mean(rgb.min(axis=1) < NEAR_WHITE))
    bad = []
    if n_colours <= MIN_COLOURS:
        bad.append(f"screenshot has {n_colours} colours (<= {MIN_COLOURS}): blank?")
    if ink <= MIN_INK:
        bad.append(f"screenshot has {ink:.2%} non-white pixels (<= {MIN_INK:.1%}): blank?")
    return bad


def check_report(driver, path: Path, *, expected_images: int | None = N_FIGURES) -> list[str]:
    """All checks of the page at ``path``; the list of everything wrong with it."""
    load(driver, path)
    return (console_problems(driver) + image_problems(driver, expected_images)
            + content_problems(driver) + screenshot_problems(driver))


# -- tests -------------------------------------------------------------------------------

def test_report_opens_cleanly_in_chromium(report, browser):
    """No console error, all six figures decode, title, claims table, painted screen."""
    problems = check_report(browser, report)
    assert not problems, "report.html in Chromium:\n  " + "\n  ".join(problems)


def _corrupt_first_image(html: str) -> tuple[str, str]:
    """Replace 64 characters in the middle of the first figure's base64 by '!', which is
    not in the base64 alphabet: the data: URL no longer decodes. Returns the new html
    and the figure's alt text."""
    m = re.search(r'<img alt="([^"]*)" src="data:image/png;base64,([A-Za-z0-9+/=]+)"', html)
    assert m, "no embedded PNG in the report"
    mid = (m.start(2) + m.end(2)) // 2
    return html[:mid] + "!" * 64 + html[mid + 64:], m.group(1)


def test_checks_catch_a_broken_report(report, browser, tmp_path):
    """A copy with one figure's base64 corrupted and a console.error injected fails the
    console and image checks, and only for those; a copy with its body hidden fails the
    screenshot check. The intact report passes, so the failures come from the defects."""
    html = report.read_text(encoding="utf-8")
    # the corruption really breaks the PNG (checked without the browser, too)
    broken, alt = _corrupt_first_image(html)
    data = re.search(r'data:image/png;base64,([^"]+)"', broken).group(1)
    with pytest.raises(ValueError):
        base64.b64decode(data, validate=True)
    broken = broken.replace("</body>", "<script>console.error('x')</script>\n</body>", 1)
    assert "console.error('x')" in broken
    bad_copy = tmp_path / "broken.html"
    bad_copy.write_text(broken, encoding="utf-8")

    load(browser, bad_copy)
    console = console_problems(browser)
    # the injected error, and Chromium's own error for the undecodable data: URL
    assert any(p.endswith('"x"') for p in console), console
    assert any("ERR_INVALID_URL" in p for p in console), console
    images = image_problems(browser, N_FIGURES)
    assert len(images) == 1 and images[0].startswith(f"image {alt}:"), images
    assert "0x0" in images[0] and "EncodingError" in images[0], images
    assert content_problems(browser) == []
    assert screenshot_problems(browser) == []
    # the same through the one-call checker: console and image problems, nothing else
    problems = check_report(browser, bad_copy)
    assert sorted(problems) == sorted(console + images), problems

    hidden = tmp_path / "hidden.html"
    hidden.write_text(html.replace("</head>", "<style>body{visibility:hidden}</style>"
                                              "</head>", 1), encoding="utf-8")
    load(browser, hidden)
    blank = screenshot_problems(browser)
    assert len(blank) == 2 and "1 colours" in blank[0], blank
