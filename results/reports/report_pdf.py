"""Headless Chromium for the report: find it, print the HTML report to PDF.

The browser is the Debian package ``chromium`` (``make test`` installs it when run as root); a
``chromium-browser`` or Google Chrome on the PATH serves as well. Nothing here needs a display or
the network: the report is one self-contained file.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from pathlib import Path

from rvcoax.errors import RvcoaxError

__all__ = ["BROWSERS", "BrowserUnavailableError", "find_browser", "headless_command", "print_pdf"]

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


class BrowserUnavailableError(RvcoaxError, RuntimeError):
    """No headless browser to print the report with; the message says what to install."""


def find_browser() -> str | None:
    """The path of the first of :data:`BROWSERS` on the PATH (``RVCOAX_BROWSER`` overrides), or None."""
    chosen = os.environ.get("RVCOAX_BROWSER")
    if chosen:
        return shutil.which(chosen) or (chosen if Path(chosen).is_file() else None)
    return next((path for path in map(shutil.which, BROWSERS) if path), None)


def headless_command(browser: str, profile: Path, *options: str) -> list[str]:
    """A headless Chromium command line with its own throw-away profile, no GPU, no first-run chatter.

    ``--no-sandbox`` is passed when running as root (CI), where Chromium refuses to start otherwise.
    """
    command = [browser, "--headless", "--disable-gpu", "--hide-scrollbars", "--no-first-run",
               "--no-default-browser-check", "--disable-extensions", f"--user-data-dir={profile}"]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        command.append("--no-sandbox")
    return command + list(options)


def print_pdf(html_path: str | Path, pdf_path: str | Path, timeout_s: float = 120.0) -> Path:
    """Print the HTML report to a PDF (A4, as the browser lays it out for print) and return its path.

    Parameters
    ----------
    html_path : str or Path
        The report (:func:`write_report`).
    pdf_path : str or Path
        The PDF, written atomically.
    timeout_s : float
        How long the browser may take.

    Returns
    -------
    Path
        ``pdf_path``.

    Raises
    ------
    BrowserUnavailableError
        No headless Chromium on the PATH, or it failed or timed out (the message says which).
    """
    browser = find_browser()
    if browser is None:
        raise BrowserUnavailableError("--pdf needs a headless Chromium and none was found on the PATH "
                                      f"({', '.join(BROWSERS)}); on Debian: apt-get install chromium. "
                                      "The HTML report was written and prints from any browser.")
    source, target = Path(html_path).resolve(), Path(pdf_path)
    target.parent.mkdir(parents=True, exist_ok=True)
    temporary = target.with_name(f".{target.stem}.{os.getpid()}.tmp.pdf")
    with tempfile.TemporaryDirectory(prefix="rvcoax-chromium-") as profile:
        command = headless_command(browser, Path(profile), "--no-pdf-header-footer",
                                   f"--print-to-pdf={temporary}", source.as_uri())
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=timeout_s)
        except subprocess.TimeoutExpired:
            temporary.unlink(missing_ok=True)
            raise BrowserUnavailableError(f"{browser} did not print {source} to PDF within {timeout_s:g} s") from None
    if done.returncode != 0 or not temporary.is_file() or temporary.stat().st_size == 0:
        temporary.unlink(missing_ok=True)
        tail = " | ".join((done.stderr or "").strip().splitlines()[-3:])
        raise BrowserUnavailableError(f"{browser} could not print {source} to PDF (exit status {done.returncode}"
                                      + (f": {tail}" if tail else "") + ")")
    os.replace(temporary, target)
    return target
