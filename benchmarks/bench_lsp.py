"""Language server benchmark: ``python3 -m cyphy lsp`` driven over stdio by a real LSP client
(pytest-lsp's), on a copy of the marXbot example.

Measured, each over ``--runs`` repetitions (medians, and the slowest):

* diagnostics: from sending a one-character edit of the marXbot p-model (``0.0575m`` ↔
  ``0.0576m``, the core's height) to receiving that file's new diagnostics; this includes the
  server's debounce pause (``cyphy.lsp.server.DEBOUNCE_S``) and the check of the whole folder;
* hover on a link (its elaborated pose), a constant (its evaluated value) and go to
  definition of a library joint, each a request's round trip;
* memory: the server's peak resident set (``VmHWM``) with the marXbot open and, when
  ``../shared/corpus`` is there, every corpus file open too.

Targets: diagnostics median ≤ 150 ms, hover and definition medians ≤ 50 ms, memory ≤ 300 MB.
Exit status 0 when all hold, 1 otherwise.

Run: ``python3 benchmarks/bench_lsp.py [--runs 20] [--no-corpus]``.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

from lsprotocol import types as lsp
from pytest_lsp import ClientServerConfig, LanguageClient

ROOT = Path(__file__).resolve().parent.parent
CORPUS = ROOT.parent / "shared" / "corpus"
TARGETS = {"diagnostics": 150.0, "hover link": 50.0, "hover constant": 50.0,
           "definition": 50.0}
MEMORY_TARGET_MB = 300.0


def _position(text: str, needle: str, skip: int = 0) -> lsp.Position:
    at = text.index(needle) + skip
    line = text.count("\n", 0, at)
    return lsp.Position(line=line, character=at - (text.rfind("\n", 0, at) + 1))


def _open(client: LanguageClient, path: Path) -> str:
    text = path.read_text(encoding="utf-8")
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        text_document=lsp.TextDocumentItem(uri=path.as_uri(), language_id="robosim",
                                           version=1, text=text)))
    return text


async def _diagnostics_of(client: LanguageClient, uri: str) -> None:
    while uri not in client.diagnostics:
        await client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)


def _cpu_ms(pid: int) -> float:
    """The server's CPU time so far (user and system): on a loaded machine the wall-clock
    latency includes waiting for a core, this does not."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) * 1000 / os.sysconf("SC_CLK_TCK")


def _peak_rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024
    return float("nan")


async def _bench(folder: Path, runs: int, corpus: bool) -> dict[str, list[float]]:
    config = ClientServerConfig(server_command=[sys.executable, "-m", "cyphy", "lsp"],
                                server_env={**os.environ, "PYTHONPATH": str(ROOT)})
    client = await config.start()
    times: dict[str, list[float]] = {k: [] for k in TARGETS}
    try:
        await client.initialize_session(lsp.InitializeParams(
            capabilities=lsp.ClientCapabilities()))
        base = folder / "marXbotBase.rsm"
        uri = base.as_uri()
        text = ""
        for path in sorted(folder.glob("*.rsm")):
            opened = _open(client, path)
            text = opened if path == base else text
        await _diagnostics_of(client, uri)
        ident = lsp.TextDocumentIdentifier(uri=uri)
        edit = _position(text, "z = 0.0575m", len("z = 0.057"))
        pid = client._server.pid  # noqa: SLF001
        cpu_before = _cpu_ms(pid)
        for i in range(runs):
            client.diagnostics.pop(uri, None)
            start = time.perf_counter()
            client.text_document_did_change(lsp.DidChangeTextDocumentParams(
                text_document=lsp.VersionedTextDocumentIdentifier(uri=uri, version=i + 2),
                content_changes=[lsp.TextDocumentContentChangePartial(
                    range=lsp.Range(start=edit, end=lsp.Position(
                        line=edit.line, character=edit.character + 1)),
                    text="6" if i % 2 == 0 else "5")]))
            await _diagnostics_of(client, uri)
            times["diagnostics"].append((time.perf_counter() - start) * 1000)
        times["diagnostics CPU"] = [(_cpu_ms(pid) - cpu_before) / runs]
        requests = {
            "hover link": (client.text_document_hover_async, lsp.HoverParams,
                           _position(text, "Wheel in LTreel")),
            "hover constant": (client.text_document_hover_async, lsp.HoverParams,
                               _position(text, "roll = PI pitch", 7)),
            "definition": (client.text_document_definition_async, lsp.DefinitionParams,
                           _position(text, "jref LHinge = Revolute", 15)),
        }
        for name, (send, params, position) in requests.items():
            for _ in range(runs):
                start = time.perf_counter()
                answer = await send(params(text_document=ident, position=position))
                times[name].append((time.perf_counter() - start) * 1000)
                assert answer is not None, name
        if corpus and CORPUS.is_dir():
            files = sorted(p for p in CORPUS.rglob("*") if p.suffix in (".pm", ".rst", ".rsm"))
            for path in files:
                _open(client, path)
            await client.text_document_hover_async(lsp.HoverParams(  # all checked by then
                text_document=lsp.TextDocumentIdentifier(uri=files[-1].as_uri()),
                position=lsp.Position(line=0, character=0)))
            times["corpus files open"] = [float(len(files))]
        times["memory MB"] = [_peak_rss_mb(pid)]
        await client.shutdown_session()
    finally:
        await client.stop()
    return times


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--no-corpus", action="store_true")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "marxbot"
        shutil.copytree(ROOT / "examples" / "marxbot", folder)
        times = asyncio.run(_bench(folder, args.runs, not args.no_corpus))
    ok = True
    for name, target in TARGETS.items():
        median, worst = statistics.median(times[name]), max(times[name])
        held = median <= target
        ok &= held
        print(f"{name:<16} median {median:7.1f} ms  max {worst:7.1f} ms  "
              f"(target ≤ {target:.0f} ms: {'ok' if held else 'MISSED'})")
    print(f"{'':<16} the server's CPU time per edit (mean): "
          f"{times['diagnostics CPU'][0]:.1f} ms; load average {os.getloadavg()[0]:.1f} "
          f"on {os.cpu_count()} cores")
    memory = times["memory MB"][0]
    ok &= memory <= MEMORY_TARGET_MB
    opened = int(times.get("corpus files open", [0])[0])
    print(f"{'memory':<16} peak {memory:7.1f} MB with the marXbot"
          f"{f' and {opened} corpus files' if opened else ''} open "
          f"(target ≤ {MEMORY_TARGET_MB:.0f} MB: "
          f"{'ok' if memory <= MEMORY_TARGET_MB else 'MISSED'})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
