"""``cyphy lsp`` end to end: a real LSP client (pytest-lsp) drives ``python3 -m cyphy lsp`` over
stdio on copies of the examples.

The diagnostics are compared with what ``cyphy check --format json`` (a separate process, the
command users run) reports for the same text saved to disk; positions, values and poses with
what the model text says, worked out by hand.
"""

from __future__ import annotations

import asyncio
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

pytest.importorskip("pygls")
pytest_lsp = pytest.importorskip("pytest_lsp")
from lsprotocol import types as lsp  # noqa: E402
from pytest_lsp import ClientServerConfig, LanguageClient  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
LIBRARY = ROOT / "cyphy" / "lang" / "library" / "physmod"
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}
SERVER = ClientServerConfig(server_command=[sys.executable, "-m", "cyphy", "lsp"],
                            server_env=ENV)


@pytest_lsp.fixture(config=SERVER)
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(lsp.InitializeParams(
        capabilities=lsp.ClientCapabilities()))
    yield
    await lsp_client.shutdown_session()


# --------------------------------------------------------------------------- helpers


def uri(path: Path) -> str:
    return path.as_uri()


def copy_example(name: str, tmp: Path) -> Path:
    target = tmp / name
    shutil.copytree(EXAMPLES / name, target)
    return target


def open_doc(client: LanguageClient, path: Path, text: str | None = None) -> str:
    text = path.read_text(encoding="utf-8") if text is None else text
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        text_document=lsp.TextDocumentItem(uri=uri(path), language_id="robosim", version=1,
                                         text=text)))
    return text


def lsp_position(text: str, at: int) -> lsp.Position:
    line = text.count("\n", 0, at)
    return lsp.Position(line=line, character=at - (text.rfind("\n", 0, at) + 1))


class Doc:
    """An open document and its text as the client knows it, edited by incremental changes."""

    def __init__(self, client: LanguageClient, path: Path) -> None:
        self.client, self.path, self.version = client, path, 1
        self.text = open_doc(client, path)

    def replace(self, start: int, end: int, new: str) -> None:
        change = lsp.TextDocumentContentChangePartial(
            range=lsp.Range(lsp_position(self.text, start), lsp_position(self.text, end)),
            text=new)
        self.text = self.text[:start] + new + self.text[end:]
        self.send([change])

    def replace_all(self, text: str) -> None:
        self.text = text
        self.send([lsp.TextDocumentContentChangeWholeDocument(text=text)])

    def send(self, changes: list) -> None:
        self.version += 1
        self.client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            text_document=lsp.VersionedTextDocumentIdentifier(uri=uri(self.path),
                                                              version=self.version),
            content_changes=changes))

    def sub(self, old: str, new: str) -> None:
        start = self.text.index(old)
        self.replace(start, start + len(old), new)

    async def diagnostics(self) -> list[lsp.Diagnostic]:
        """The diagnostics after every change sent so far: a request is answered only after
        the pending check ran (and its diagnostics were sent, before the answer)."""
        await self.client.text_document_document_symbol_async(lsp.DocumentSymbolParams(
            text_document=lsp.TextDocumentIdentifier(uri=uri(self.path))))
        return list(self.client.diagnostics.get(uri(self.path), []))

    def at(self, needle: str, offset: int = 0, nth: int = 0) -> lsp.Position:
        start = -1
        for _ in range(nth + 1):
            start = self.text.index(needle, start + 1)
        return lsp_position(self.text, start + offset)

    def ident(self) -> lsp.TextDocumentIdentifier:
        return lsp.TextDocumentIdentifier(uri=uri(self.path))


def cyphy_check(path: Path, text: str) -> list[tuple[str, tuple[int, int, int, int], str]]:
    """What ``cyphy check --format json FILE`` reports for ``text`` saved at ``path``:
    (code, 0-based range, message with hint) of that file's diagnostics."""
    path.write_text(text, encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "cyphy", "check", "--format", "json",
                           str(path)], capture_output=True, text=True, env=ENV, timeout=120)
    assert done.returncode in (0, 1), done.stderr
    out = []
    for d in json.loads(done.stdout):
        s = d["span"]
        if s["file"] != str(path):
            continue
        message = d["message"] + "".join(f"\nnote: {n}" for n in d["notes"]) + (
            f"\nhint: {d['hint']}" if d["hint"] else "")
        rng = (max(s["line"] - 1, 0), max(s["column"] - 1, 0), max(s["end_line"] - 1, 0),
               max(s["end_column"] - 1, 0))
        out.append((d["code"], rng, message))
    return sorted(out)


def seen(diagnostics: list[lsp.Diagnostic]) -> list[tuple[str, tuple[int, int, int, int], str]]:
    return sorted((str(d.code), (d.range.start.line, d.range.start.character,
                                 d.range.end.line, d.range.end.character), d.message)
                  for d in diagnostics)


# --------------------------------------------------------------------------- diagnostics


@pytest.mark.asyncio
async def test_marxbot_is_clean_and_an_edit_gets_cyphy_checks_diagnostic(
        client: LanguageClient, tmp_path: Path) -> None:
    folder = copy_example("marxbot", tmp_path)
    doc = Doc(client, folder / "marXbotBase.rsm")
    for other in ("Treel.rsm", "Mapping.rsm"):  # several open files of one folder
        open_doc(client, folder / other)
    await client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    assert await doc.diagnostics() == []
    assert list(client.diagnostics[uri(folder / "Treel.rsm")]) == []

    doc.sub("roll = PI pitch", "roll = PIE pitch")  # an unknown name: S1 with a hint
    got = seen(await doc.diagnostics())
    assert [g[0] for g in got] == ["S1"] and "did you mean 'PI'" in got[0][2]
    assert got == cyphy_check(tmp_path / "marxbot" / "marXbotBase.rsm", doc.text)

    doc.sub("roll = PIE pitch", "roll = PI pitch")
    assert await doc.diagnostics() == []


FIXED_ARM = ("import physmod::joints::*\npmodel Arm {", "Revolute {", "")


@pytest.mark.asyncio
async def test_faulty_errors_typed_in_match_cyphy_check_and_clear(
        client: LanguageClient, tmp_path: Path) -> None:
    """Start from a correct arm, type in the two mistakes of examples/faulty (a misspelt
    joint definition, a geometry in a link's own definition), then take them out."""
    folder = copy_example("faulty", tmp_path)
    path = folder / "arm.rsm"
    faulty = path.read_text(encoding="utf-8")
    box = re.search(r"\t+box\(length = 0.05, width = 0.05\)[^\n]*\n", faulty)
    assert box is not None
    correct = (faulty.replace("pmodel Arm {", FIXED_ARM[0]).replace("Revolte {", FIXED_ARM[1])
               .replace(box.group(0), ""))
    path.write_text(correct, encoding="utf-8")
    doc = Doc(client, path)
    assert await doc.diagnostics() == []

    doc.sub("Revolute {", "Revolte {")
    doc.sub("import physmod::joints::*\n", "")
    anchor = doc.text.index("inertial information { mass 0.5 }")
    line_end = doc.text.index("\n", anchor) + 1
    doc.replace(line_end, line_end, box.group(0))
    assert doc.text == faulty
    got = seen(await doc.diagnostics())
    assert sorted(g[0] for g in got) == ["E-MEMBER", "S1"]
    assert got == cyphy_check(tmp_path / "faulty" / "arm.rsm", doc.text)
    assert any("did you mean 'Revolute'?" in g[2] for g in got)  # the hint travels

    doc.replace_all(correct)
    assert await doc.diagnostics() == []


@pytest.mark.asyncio
async def test_a_broken_file_keeps_the_server_and_other_files_diagnostics(
        client: LanguageClient, tmp_path: Path) -> None:
    folder = copy_example("marxbot", tmp_path)
    base = Doc(client, folder / "marXbotBase.rsm")
    treel = Doc(client, folder / "Treel.rsm")
    base.sub("pmodel marXbotBase {", "pmodel marXbotBase { local link {{")  # half typed
    treel.sub("z = 0 roll = PI/2", "z = 0 roll = PIE/2")
    broken = seen(await base.diagnostics())
    assert [b[0] for b in broken] == ["E-SYNTAX"]
    other = seen(await treel.diagnostics())
    assert [o[0] for o in other] == ["S1"] and "'PIE'" in other[0][2]
    assert other == cyphy_check(folder / "Treel.rsm", treel.text)
    hover = await client.text_document_hover_async(lsp.HoverParams(
        text_document=base.ident(), position=base.at("roll = PI", 7)))
    assert hover is None or hover.contents  # answered, whatever it knows


# --------------------------------------------------------------------------- navigation


def library_line(file: str, pattern: str) -> int:
    """The 0-based line of the library file that declares ``pattern`` (read by hand)."""
    lines = (LIBRARY / file).read_text(encoding="utf-8").splitlines()
    return next(i for i, ln in enumerate(lines) if re.search(pattern, ln))


@pytest.mark.asyncio
async def test_definition_and_references(client: LanguageClient, tmp_path: Path) -> None:
    folder = copy_example("marxbot", tmp_path)
    doc = Doc(client, folder / "marXbotBase.rsm")

    found = await client.text_document_definition_async(lsp.DefinitionParams(
        text_document=doc.ident(),
        position=doc.at("jref LHinge = Revolute", 15)))  # into the library
    assert isinstance(found, lsp.Location)
    assert found.uri == uri(LIBRARY / "joints.rsm")
    assert found.range.start.line == library_line("joints.rsm", r"^\s*joint Revolute\b")

    found = await client.text_document_definition_async(lsp.DefinitionParams(
        text_document=doc.ident(),
        position=doc.at("Wheel in LTreel", 0)))  # a link of another file's p-model
    assert found.uri == uri(folder / "Treel.rsm")
    treel = (folder / "Treel.rsm").read_text(encoding="utf-8").splitlines()
    assert treel[found.range.start.line].strip().startswith("local link Wheel")

    found = await client.text_document_definition_async(lsp.DefinitionParams(
        text_document=doc.ident(), position=doc.at("roll = PI pitch", 7)))  # a library constant
    assert found.uri == uri(LIBRARY / "math.rsm")
    assert found.range.start.line == library_line("math.rsm", r"const PI\b")

    refs = await client.text_document_references_async(lsp.ReferenceParams(
        text_document=doc.ident(), position=doc.at("part LTreel = Treel", 15),
        context=lsp.ReferenceContext(include_declaration=False)))
    lines = sorted(r.range.start.line for r in refs)  # the import and the two parts
    text = doc.text.splitlines()
    assert [text[n].strip()[:12] for n in lines] == ["import marXb", "part LTreel ",
                                                     "part RTreel "]


@pytest.mark.asyncio
async def test_machine_names_go_to_states_events_operations_and_constants(
        client: LanguageClient, tmp_path: Path) -> None:
    folder = copy_example("marxbot", tmp_path)
    doc = Doc(client, folder / "marXbotSoftware.rsm")
    lines = doc.text.splitlines()

    async def declared(position: lsp.Position) -> str:
        found = await client.text_document_definition_async(lsp.DefinitionParams(
            text_document=doc.ident(), position=position))
        assert isinstance(found, lsp.Location) and found.uri == uri(doc.path)
        return lines[found.range.start.line].strip()

    assert await declared(doc.at("from Forward to Cruising", 5)) == "state Forward {"
    assert await declared(doc.at("to Cruising }", 3)) == "state Cruising {}"
    assert await declared(doc.at("condition $obstacle", 11)) == "event obstacle"
    assert (await declared(doc.at("entry $move(lv, 0)", 7))).startswith("move(")
    assert (await declared(doc.at("entry $move(lv, 0)", 12))).startswith("const lv: real")

    refs = await client.text_document_references_async(lsp.ReferenceParams(
        text_document=doc.ident(), position=doc.at("event obstacle", 6),
        context=lsp.ReferenceContext(include_declaration=True)))
    conditions = [r for r in refs if "$obstacle" in lines[r.range.start.line]]
    by_hand = [n for n, ln in enumerate(lines) if "$obstacle" in ln and "//" not in ln]
    assert sorted(r.range.start.line for r in conditions) == by_hand


@pytest.mark.asyncio
async def test_hover_shows_values_units_poses_and_signatures(
        client: LanguageClient, tmp_path: Path) -> None:
    folder = copy_example("marxbot", tmp_path)
    mapping = Doc(client, folder / "Mapping.rsm")
    base = Doc(client, folder / "marXbotBase.rsm")

    hover = await client.text_document_hover_async(lsp.HoverParams(
        text_document=mapping.ident(),
        position=mapping.at("/axisLength", 1)))  # a use, resolved to the constant
    assert "const axisLength: real = 0.06m" in hover.contents.value
    assert "value: `0.06 m`" in hover.contents.value

    # The left wheel, by hand: LTreel at (0, 0.03, 0.025) rolled by pi; the wheel at
    # (0, -DEPTH, 0) = (0, -0.03, 0) in the treel, rolled by pi/2. Rolling by pi turns
    # (0, -0.03, 0) into (0, 0.03, 0): the wheel is at (0, 0.06, 0.025), rolled by
    # pi + pi/2 = -pi/2. The right one: (0, -0.03 - 0.03, 0.025), rolled by pi/2.
    hover = await client.text_document_hover_async(lsp.HoverParams(
        text_document=base.ident(), position=base.at("Wheel in LTreel")))
    assert "`marXbotBase::LTreel::Wheel`: (0, 0.06, 0.025, -1.5708, 0, 0)" \
        in hover.contents.value
    assert "`marXbotBase::RTreel::Wheel`: (0, -0.06, 0.025, 1.5708, 0, 0)" \
        in hover.contents.value

    hover = await client.text_document_hover_async(lsp.HoverParams(
        text_document=base.ident(), position=base.at("jref LHinge = Revolute", 15)))
    assert "joint Revolute" in hover.contents.value and "input tau: real" in hover.contents.value
    assert "physmod/joints.rsm" in hover.contents.value


# --------------------------------------------------------------------------- completion, outline


def labels(result: lsp.CompletionList | list | None) -> set[str]:
    items = result.items if isinstance(result, lsp.CompletionList) else (result or [])
    return {i.label for i in items}


@pytest.mark.asyncio
async def test_completion(client: LanguageClient, tmp_path: Path) -> None:
    folder = copy_example("marxbot", tmp_path)
    doc = Doc(client, folder / "marXbotBase.rsm")
    start = doc.text.index("import physmod::math::*")
    doc.replace(start, start, "import physmod::joints::\n")
    got = labels(await client.text_document_completion_async(lsp.CompletionParams(
        text_document=doc.ident(),
        position=doc.at("import physmod::joints::\n", len("import physmod::joints::")))))
    by_hand = set(re.findall(r"^\s*joint (\w+)", (LIBRARY / "joints.rsm").read_text(),
                             re.MULTILINE))
    assert by_hand and by_hand <= got
    got = labels(await client.text_document_completion_async(lsp.CompletionParams(
        text_document=doc.ident(),
        position=doc.at("import physmod::joints::\n", len("import physmod::")))))
    assert {"joints", "sensors", "actuators", "math", "sdf"} <= got

    inside = doc.at("local link Core {", len("local link Core {"))  # inside a link
    got = labels(await client.text_document_completion_async(lsp.CompletionParams(
        text_document=doc.ident(), position=lsp.Position(line=inside.line + 1, character=2))))
    assert {"pose", "def", "jref", "sref", "PI", "Core", "LTreel", "Revolute"} <= got

    inside = doc.at("annotation Revolute {", len("annotation Revolute {"))
    got = labels(await client.text_document_completion_async(lsp.CompletionParams(
        text_document=doc.ident(), position=lsp.Position(line=inside.line + 1, character=0))))
    assert "axis" in got  # a field of the Revolute annotation template


@pytest.mark.asyncio
async def test_document_symbols(client: LanguageClient, tmp_path: Path) -> None:
    folder = copy_example("marxbot", tmp_path)
    doc = Doc(client, folder / "marXbotBase.rsm")
    symbols = await client.text_document_document_symbol_async(lsp.DocumentSymbolParams(
        text_document=doc.ident()))
    assert [s.name for s in symbols] == ["marXbotBase"]
    top = {c.name: c for c in symbols[0].children}
    assert {"LTreel", "RTreel", "Core"} <= set(top)
    core = {c.name for c in top["Core"].children}
    assert {"Proximity", "LHinge", "RHinge", "Acc", "Gyro"} <= core
    assert top["Core"].selection_range.start == doc.at("local link Core", 11)


# --------------------------------------------------------------------------- fuzzed edits

PIECES = ["{", "}", "(", ")", "=", ":", "::", ",", ".", " ", "\n", "link", "local link L {",
          "pose {", "x = ", "0.5m", "PI", "const c: real = ", "jref J = Revolute {", "import ",
          "physmod::", "@", "'", "\"", "//", "/*", "é", "∀", "\t"]


@st.composite
def edits(draw: st.DrawFn) -> list[tuple[float, int, str]]:
    """Incremental edits: where (a fraction of the text's length), how many characters to
    delete, what to insert."""
    return draw(st.lists(st.tuples(
        st.floats(0, 1), st.integers(0, 12),
        st.lists(st.sampled_from(PIECES), max_size=4).map("".join)), min_size=1, max_size=8))


async def fuzz_session(folder: Path, name: str, changes: list[tuple[float, int, str]]
                       ) -> tuple[list, list]:
    client = await SERVER.start()
    try:
        await client.initialize_session(lsp.InitializeParams(
            capabilities=lsp.ClientCapabilities()))
        doc = Doc(client, folder / name)
        for where, delete, insert in changes:
            start = int(where * len(doc.text))
            doc.replace(start, min(len(doc.text), start + delete), insert)
            # Requests between edits, answered whatever state the text is in.
            position = lsp_position(doc.text, start)
            await client.text_document_hover_async(lsp.HoverParams(
                text_document=doc.ident(), position=position))
            await client.text_document_completion_async(lsp.CompletionParams(
                text_document=doc.ident(), position=position))
        doc.replace_all(doc.text)  # a full re-sync
        got = seen(await doc.diagnostics())
        errors = [m.message for m in client.log_messages
                  if m.type == lsp.MessageType.Error]
        await client.shutdown_session()
        return got, errors
    finally:
        await client.stop()


@pytest.mark.parametrize("name", ["Mapping.rsm", "Treel.rsm"])
def test_fuzzed_edits_never_crash_and_resync_to_cyphy_check(name: str,
                                                           tmp_path_factory) -> None:
    @settings(max_examples=4, deadline=None, derandomize=True,
              suppress_health_check=list(HealthCheck))
    @given(edits())
    def one(changes: list[tuple[float, int, str]]) -> None:
        folder = copy_example("marxbot", tmp_path_factory.mktemp("fuzz"))
        got, errors = asyncio.run(fuzz_session(folder, name, changes))
        assert errors == []  # no request or check failed inside the server
        text = (folder / name).read_text(encoding="utf-8")
        for where, delete, insert in changes:
            start = int(where * len(text))
            text = text[:start] + insert + text[min(len(text), start + delete):]
        assert got == cyphy_check(folder / name, text)

    one()


def test_positions_are_utf16_code_units_both_ways() -> None:
    """LSP counts UTF-16 code units; cyphy counts code points from 1. A character outside
    the Basic Multilingual Plane is two units (by hand: '𝜃' is U+1D703)."""
    from cyphy.lsp.server import from_lsp, to_lsp

    text = "const a: real = 1\n// 𝜃é x\n"
    assert to_lsp(text, 2, 6) == lsp.Position(line=1, character=6)  # " " after "// 𝜃é"
    assert to_lsp(text, 2, 7) == lsp.Position(line=1, character=7)
    assert from_lsp(text, lsp.Position(line=1, character=7)) == (2, 7)
    assert from_lsp(text, lsp.Position(line=0, character=6)) == (1, 7)
