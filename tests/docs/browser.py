"""A headless Chromium driven over the DevTools protocol (a websocket), for the site tests: open a page,
wait for it, MathJax and its images, and return what a reader would see go wrong (console errors, uncaught
exceptions, failed loads). Needs Debian's ``chromium`` and ``websocket-client``; downloads nothing."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import tempfile
import time
import urllib.request
from dataclasses import dataclass, field

__all__ = ["find_chromium", "PageReport", "Chromium"]

#: waits for MathJax's typesetting, for every image (each forced to load eagerly) and for every video's
#: metadata (its first frame's size), then reports
PAGE_PROBE = """(async () => {
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) { await MathJax.startup.promise; }
  const imgs = Array.from(document.images);
  imgs.forEach(i => { i.loading = 'eager'; });
  await Promise.all(imgs.map(i => i.complete ? null : new Promise(r => { i.onload = i.onerror = r; })));
  const vids = Array.from(document.querySelectorAll('video'));
  await Promise.all(vids.map(v => v.readyState >= 1 ? null : new Promise(r => {
    v.addEventListener('loadedmetadata', r); v.addEventListener('error', r, true); setTimeout(r, 15000); v.load(); })));
  return {
    videos: vids.map(v => ({ready: v.readyState, width: v.videoWidth, duration: v.duration,
                            error: v.error ? v.error.code : 0, network: v.networkState})),
    images: imgs.map(i => ({src: i.getAttribute('src'), complete: i.complete, width: i.naturalWidth})),
    math: document.querySelectorAll('.math').length,
    mjx: document.querySelectorAll('mjx-container').length,
    mjx_errors: document.querySelectorAll('mjx-merror').length,
    mathjax: !!(window.MathJax && MathJax.version),
    title: document.title,
    raw: rawText(),
  };
})()"""

#: what a reader would see unrendered, from the text a page shows (code blocks and streams left out, where
#: pipes and dollars are code): a Markdown table's pipes (a separator row "|---|" or a run of 4+ pipes), TeX
#: still between dollars, a Mermaid diagram's source, and a "... is not installed" hint in a cell's output
RAW_TEXT = """function rawText() {
  const skip = 'pre, code, script, style, textarea, mjx-container, .highlight, .math, nav, .sidebar-drawer, .toc-drawer';
  const main = document.querySelector('article') || document.body;
  const walker = document.createTreeWalker(main, NodeFilter.SHOW_TEXT);
  const out = {pipes: [], dollars: [], mermaid: [], nag: []};
  const snip = t => t.replace(/\\s+/g, ' ').trim().slice(0, 120);
  let node;
  while ((node = walker.nextNode())) {
    const el = node.parentElement;
    const t = node.textContent;
    if (el.closest('.cell_output') && /is not installed/.test(t)) out.nag.push(snip(t));
    if (el.closest(skip)) continue;
    if (/\\|\\s*:?-{3,}/.test(t) || (t.match(/\\s\\|\\s/g) || []).length >= 3) out.pipes.push(snip(t));
    if (/(^|[^\\\\$])\\$[^$\\s][^$]*[^$\\s\\\\]\\$|(^|[^\\\\$])\\$[^$\\s]\\$/.test(t)) out.dollars.push(snip(t));
  }
  document.querySelectorAll('pre, code').forEach(el => {
    const t = el.textContent.trim();
    if (/^(flowchart|graph)\\s+(LR|RL|TD|TB|BT)\\b|^(sequenceDiagram|classDiagram|stateDiagram)/.test(t)
        || el.closest('.highlight-mermaid, .language-mermaid')) out.mermaid.push(snip(t));
  });
  return out;
}"""

PAGE_PROBE = PAGE_PROBE.replace("(async () => {", RAW_TEXT + "\n(async () => {", 1)


def find_chromium() -> str | None:
    """The Chromium executable on PATH (Debian's ``chromium``), or ``None``."""
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


@dataclass
class PageReport:
    """What a page did: its console errors and uncaught exceptions, failed loads, and the probe's result
    (images with their natural widths [px], the counts of math elements and MathJax's output elements)."""

    url: str
    errors: list[str] = field(default_factory=list)
    probe: dict = field(default_factory=dict)


class Chromium:
    """One headless Chromium (its own profile in a temporary folder) and one tab, driven over the DevTools
    protocol. Use as a context manager."""

    def __init__(self, executable: str, timeout_s: float = 60.0) -> None:
        self.executable, self.timeout_s = executable, timeout_s
        self._profile = tempfile.mkdtemp(prefix="lipmpcc-chromium-")
        self._proc: subprocess.Popen | None = None
        self._ws = None
        self._next_id = 0
        self._events: list[dict] = []

    def __enter__(self) -> "Chromium":
        import websocket  # websocket-client

        args = [self.executable, "--headless", "--disable-gpu", "--no-first-run", "--no-default-browser-check",
                "--disable-extensions", "--disable-background-networking", "--remote-debugging-port=0",
                f"--user-data-dir={self._profile}", "--window-size=1280,900", "about:blank"]
        if hasattr(os, "geteuid") and os.geteuid() == 0:
            args.insert(1, "--no-sandbox")  # Chromium refuses to run as root with its sandbox (CI runs as root)
        self._proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        port = self._devtools_port()
        deadline = time.monotonic() + self.timeout_s
        while True:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10) as resp:
                pages = [t for t in json.load(resp) if t.get("type") == "page"]
            if pages or time.monotonic() > deadline:
                break
            time.sleep(0.1)
        if not pages:
            raise RuntimeError("chromium opened no tab")
        self._ws = websocket.create_connection(pages[0]["webSocketDebuggerUrl"], timeout=self.timeout_s,
                                               suppress_origin=True)
        for domain in ("Page", "Runtime", "Log", "Network"):
            self.call(f"{domain}.enable")
        return self

    def _devtools_port(self) -> int:
        deadline = time.monotonic() + self.timeout_s
        seen = []
        while time.monotonic() < deadline:
            line = self._proc.stderr.readline()
            if not line:
                if self._proc.poll() is not None:
                    break
                continue
            seen.append(line)
            m = re.search(r"DevTools listening on ws://[^:]+:(\d+)/", line)
            if m:
                return int(m.group(1))
        raise RuntimeError("chromium did not start its DevTools endpoint: " + "".join(seen[-20:]))

    def __exit__(self, *exc) -> None:
        if self._ws is not None:
            self._ws.close()
        if self._proc is not None:
            self._proc.terminate()
            try:
                self._proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self._proc.kill()
                self._proc.wait()
        shutil.rmtree(self._profile, ignore_errors=True)

    def _receive(self) -> dict:
        return json.loads(self._ws.recv())

    def call(self, method: str, **params) -> dict:
        """Send a command and return its result (events that arrive meanwhile are kept)."""
        self._next_id += 1
        msg_id = self._next_id
        self._ws.send(json.dumps({"id": msg_id, "method": method, "params": params}))
        while True:
            msg = self._receive()
            if msg.get("id") == msg_id:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            self._events.append(msg)

    def _wait_event(self, method: str) -> None:
        deadline = time.monotonic() + self.timeout_s
        while not any(e.get("method") == method for e in self._events):
            if time.monotonic() > deadline:
                raise TimeoutError(f"no {method} within {self.timeout_s} s")
            self._events.append(self._receive())

    def open(self, url: str) -> PageReport:
        """Load ``url``, wait for its load event, MathJax and its images; report its errors and the probe."""
        self._events.clear()
        nav = self.call("Page.navigate", url=url)
        report = PageReport(url)
        if nav.get("errorText"):
            report.errors.append(f"navigation failed: {nav['errorText']}")
            return report
        self._wait_event("Page.loadEventFired")
        res = self.call("Runtime.evaluate", expression=PAGE_PROBE, awaitPromise=True, returnByValue=True)
        if "exceptionDetails" in res:
            report.errors.append(f"probe failed: {res['exceptionDetails'].get('text')}")
        report.probe = res.get("result", {}).get("value") or {}
        self.call("Runtime.evaluate", expression="1")  # collect the events that the probe's work caused
        report.errors += _errors(self._events)
        return report


def _errors(events: list[dict]) -> list[str]:
    out = []
    for e in events:
        method, p = e.get("method"), e.get("params", {})
        if method == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            out.append("console.error: " + " ".join(str(a.get("value", a.get("description", ""))) for a in p["args"]))
        elif method == "Runtime.exceptionThrown":
            d = p["exceptionDetails"]
            out.append(f"uncaught: {d.get('exception', {}).get('description') or d.get('text')}")
        elif method == "Log.entryAdded" and p["entry"].get("level") == "error" \
                and not p["entry"].get("url", "").endswith("/favicon.ico"):  # the browser's own request
            out.append(f"log: {p['entry'].get('text')} {p['entry'].get('url', '')}".strip())
        elif method == "Network.loadingFailed" and not p.get("canceled"):
            out.append(f"load failed: {p.get('errorText')} ({p.get('type')})")
    return out
