"""Well-formedness on RoboTool's examples (../shared/corpus; skipped when absent).

Every diagnostic the checks give on the corpus is listed here with what is really wrong with
the model. Many corpus models are deliberately odd (they test RoboTool's SDF generator), and
sdf-robotool.md section 6 lists the defects RoboTool itself passes on; the checks find them.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest

from cyphy import api
from conftest import CORPUS, corpus_project_folders, needs_corpus

ZERO_TRACK = ("V2", "the Treel's Top and Bottom boxes have height 0 (sdf-robotool.md 6: "
              "degenerate geometry; a warning: libsdformat and PyBullet load it)")
SINGULAR_SECOND_LINK = ("V1", "second_link's inertia has ixx = 0 (sdf-robotool.md 6: invalid "
                        "inertia, TwoBodies*)")
SAME_PLACE = ("V5", "links Tip and Rod are identical spheres at z = 0.9: copies of one link")

ERRORS: dict[str, list[tuple[str, int, str]]] = {
    "14_LinkRef": [("V1", 1, "ixx = izz = 0 with off-diagonal terms (sdf-robotool.md 6)")],
    "29_testvar": [("V1", 1, "mass (f-d)/2 ... = -18 (sdf-robotool.md 6: mass -18)")],
    "75_jointtest": [("IX3", 1, "joint R (one joint) to the 2 copies of L2: RoboTool makes two "
                      "joints named L1::R (sdf-robotool.md 1.8)")],
    "77_jointtest": [("IX3", 1, "joint R (one joint) to L2 in the 2 copies of part p")],
    "Index/IndexedJointToIndexedLink": [("IX3", 1, "PJ (4 copies) to Top (2 copies): "
                                         "RoboTool's 4x2 product (IJTIL)")],
    "Index/IndexedJointToIndexedPart": [("IX3", 1, "joint PJ (one joint) to L2 in the 2 "
                                         "copies of part p (sdf-robotool.md 1.8)")],
    "BodyPlusSonarSensorRef": [("AN3", 1, "sonar = Sonar {…} where SonarDetails is meant "
                                "(notation.md C.1)")],
    "SimpleArm": [("V1", 2, "the fingers' inertia 0.000283 / 7.52e-05 / 0.00209 breaks "
                   "ixx + iyy >= izz"),
                  ("S3", 3, "X_CF/X_FM declared 3x4 but equated to 4x3 literals")],
    "TwoBodiesPlusInertia": [("V1", 1, "body bd's inertia (0 1 2.3 1.2 0.5 0) is not positive "
                              "definite (sdf-robotool.md 6)")],
    "TwoBodiesPlusJoint": [(SINGULAR_SECOND_LINK[0], 1, SINGULAR_SECOND_LINK[1])],
    "TwoBodiesPlusJointRef": [(SINGULAR_SECOND_LINK[0], 1, SINGULAR_SECOND_LINK[1])],
    "TwoBodiesPlusPrismaticJoint": [(SINGULAR_SECOND_LINK[0], 1, SINGULAR_SECOND_LINK[1])],
    "TwoBodiesPlusPrismaticJoint_ReverseParentChild": [
        (SINGULAR_SECOND_LINK[0], 1, SINGULAR_SECOND_LINK[1])],
    "TwoBodiesPlusRevoluteJoint": [(SINGULAR_SECOND_LINK[0], 1, SINGULAR_SECOND_LINK[1])],
    "TwoBodiesPlusRevoluteJoint_ReverseParentChild": [
        (SINGULAR_SECOND_LINK[0], 1, SINGULAR_SECOND_LINK[1])],
    "TwoLinksPlusFixedConnection": [("V1", 1, "Tip's inertia (0 1 2.3 1.2 0.5 0), "
                                     "sdf-robotool.md 6")],
}
WARNINGS: dict[str, list[tuple[str, int, str]]] = {
    "21_BaseModule": [(*ZERO_TRACK[:1], 4, ZERO_TRACK[1])],
    "marXbot": [(*ZERO_TRACK[:1], 4, ZERO_TRACK[1]),
                ("STM15", 3, "SMovement's PI, lv and av are open: a family of machines, "
                 "as the paper allows; simulate and reach need their values")],
    "marXbot_simple": [(*ZERO_TRACK[:1], 4, ZERO_TRACK[1])],
    "24_BodyContact": [(SAME_PLACE[0], 1, SAME_PLACE[1])],
    "83_BodyContact": [(SAME_PLACE[0], 1, SAME_PLACE[1])],
    "84_BodyContact": [(SAME_PLACE[0], 1, SAME_PLACE[1])],
    "70_jointtest": [("V5", 2, "parts p1, p2 and link L4 put the same box at the origin")],
}

def _rel(p: Path) -> str:
    return str(p.relative_to(CORPUS))


@needs_corpus
@pytest.mark.parametrize("folder", corpus_project_folders(), ids=_rel)
def test_corpus_wellformedness(folder: Path) -> None:
    files = sorted(p for p in folder.iterdir() if p.suffix in (".pm", ".rst"))
    diagnostics = api.check(files).report.diagnostics
    errors = Counter(d.code.id for d in diagnostics if d.severity.value == "ERROR")
    warnings = Counter(d.code.id for d in diagnostics
                       if d.severity.value == "WARNING" and d.code.id != "L4")
    expected_errors = Counter({c: n for c, n, _ in ERRORS.get(_rel(folder), [])})
    expected_warnings = Counter({c: n for c, n, _ in WARNINGS.get(_rel(folder), [])})
    assert errors == expected_errors, [(d.code.id, d.message) for d in diagnostics]
    assert warnings == expected_warnings, [(d.code.id, d.message) for d in diagnostics]


@needs_corpus
def test_corpus_lists_are_current() -> None:
    """Every folder named above exists (a renamed example must not hide a finding)."""
    folders = {_rel(f) for f in corpus_project_folders()}
    assert set(ERRORS) | set(WARNINGS) <= folders


@needs_corpus
def test_l4_fires_on_exactly_the_links_without_inertials() -> None:
    """L4 warns about 195 corpus links, each of which, elaborated, has no inertial from its
    definition or its bodies: RoboTool invents mass 1 and an identity inertia for them
    (sdf-robotool.md 1.3); sdf.md decision 7 asks for L4."""
    from cyphy.diagnostics import Report
    from cyphy.model.choose import top_level_pmodels
    from cyphy.model.elaborate import elaborate_pmodel
    from cyphy.wellformed import WFContext, check_wellformed

    warned = 0
    for folder in corpus_project_folders():
        files = sorted(p for p in folder.iterdir() if p.suffix in (".pm", ".rst"))
        checked = api.check(files, api.CheckOptions(wellformedness=False))
        check_wellformed(WFContext(checked.workspace, checked.resolution, checked.report),
                         only={"L4"})
        l4 = [d for d in checked.report.diagnostics if d.code.id == "L4"]
        warned += len(l4)
        without = set()
        for pm, file in top_level_pmodels(checked.workspace):
            model = elaborate_pmodel(checked.workspace, checked.resolution, Report(), pm, file)
            without |= {link.simple_name for link in model.links if link.inertial is None}
        for d in l4:  # "link LLink::Tip has no inertial information: …"
            assert d.message.split()[1].rsplit("::", 1)[-1] in without, (_rel(folder), d.message)
    assert warned == 195
