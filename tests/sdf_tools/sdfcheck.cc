// sdfcheck: validate SDF files with libsdformat 12, the way `ign sdf -k` does.
//
//   sdfcheck [--strict] [--lints] FILE...
//
// For each FILE it prints `OK FILE`, or one `ERROR FILE: MESSAGE` line per
// problem. The exit status is 0 iff every file passed (2 on a usage error).
//
// Always (exactly `ign sdf -k` of SDFormat 12, src/ign.cc cmdCheck):
//   1. sdf::Root::Load with the default ParserConfig. Its errors (printed as
//      `CODE_NAME: message`, followed by the parser's console lines as
//      `parser said: ...`) include bad XML, missing/invalid attributes (e.g. an
//      unknown sensor type), duplicate link/joint names in a model and invalid
//      mass or inertia (LINK_INERTIA_INVALID). Like ign, nothing below runs
//      after a failed load, except the lints.
//   2. checkCanonicalLinkNames, checkJointParentChildLinkNames,
//      checkFrameAttachedToGraph, checkPoseRelativeToGraph and
//      recursiveSiblingUniqueNames. The library prints their details to
//      std::cerr; we capture that and name the clashing siblings ourselves.
// --strict: load a second time with WarningsPolicy and
//      UnrecognizedElementsPolicy = ERR, so unknown elements are errors
//      (`strict: ...`). `<initial_position>` in `<axis>` (valid in SDF 1.6,
//      removed by the 1.9 conversion libsdformat 12 applies) is whitelisted.
// --lints: tree rules that SDFormat accepts but tree importers (Bullet, URDF)
//      reject or read differently (`lint KIND: ...`): joint_no_axis,
//      axis_no_limit (libsdformat silently fills in +-1e16), multi_parent,
//      disconnected.
#include <iostream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <sdf/sdf.hh>

namespace {

using Messages = std::vector<std::string>;

// Runs f() with std::cerr redirected into `out`.
template <class F>
auto captureCerr(std::string &out, F f) {
  std::ostringstream buffer;
  auto *old = std::cerr.rdbuf(buffer.rdbuf());
  auto result = f();
  std::cerr.rdbuf(old);
  out = buffer.str();
  return result;
}

std::string oneLine(std::string s) {
  for (char &c : s)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// Console text minus colour codes, one message per line.
Messages consoleLines(const std::string &text) {
  Messages lines;
  std::string line;
  for (size_t i = 0; i <= text.size(); ++i) {
    if (i < text.size() && text[i] == '\x1b') {
      while (i < text.size() && text[i] != 'm') ++i;
    } else if (i == text.size() || text[i] == '\n') {
      if (!oneLine(line).empty()) lines.push_back(oneLine(line));
      line.clear();
    } else {
      line += text[i];
    }
  }
  return lines;
}

// sdf::ErrorCode names, in enum order (SDFormat 12.3, sdf/Error.hh).
const char *const kCodeNames[] = {
    "NONE", "FILE_READ", "DUPLICATE_NAME", "RESERVED_NAME", "ATTRIBUTE_MISSING",
    "ATTRIBUTE_INVALID", "ATTRIBUTE_DEPRECATED", "ATTRIBUTE_INCORRECT_TYPE",
    "ELEMENT_MISSING", "ELEMENT_INVALID", "ELEMENT_DEPRECATED", "ELEMENT_INCORRECT_TYPE",
    "URI_INVALID", "URI_LOOKUP", "DIRECTORY_NONEXISTANT", "MODEL_CANONICAL_LINK_INVALID",
    "MODEL_WITHOUT_LINK", "NESTED_MODELS_UNSUPPORTED", "LINK_INERTIA_INVALID",
    "JOINT_CHILD_LINK_INVALID", "JOINT_PARENT_LINK_INVALID", "JOINT_PARENT_SAME_AS_CHILD",
    "FRAME_ATTACHED_TO_INVALID", "FRAME_ATTACHED_TO_CYCLE", "FRAME_ATTACHED_TO_GRAPH_ERROR",
    "POSE_RELATIVE_TO_INVALID", "POSE_RELATIVE_TO_CYCLE", "POSE_RELATIVE_TO_GRAPH_ERROR",
    "STRING_READ", "MODEL_PLACEMENT_FRAME_INVALID", "VERSION_DEPRECATED",
    "MERGE_INCLUDE_UNSUPPORTED"};

std::string describe(const sdf::Error &e) {
  std::ostringstream s;
  const auto code = static_cast<size_t>(e.Code());
  s << (code < std::size(kCodeNames) ? kCodeNames[code] : "code " + std::to_string(code))
    << ": " << oneLine(e.Message());
  if (e.XmlPath()) s << " at " << *e.XmlPath();
  if (e.LineNumber()) s << " (line " << *e.LineNumber() << ")";
  return s.str();
}

std::string label(const sdf::ElementPtr &e) {
  std::string s = "<" + e->GetName();
  if (e->HasAttribute("name")) s += " name=\"" + e->Get<std::string>("name") + "\"";
  return s + ">";
}

// The names recursiveSiblingUniqueNames objects to, one message per clash.
void siblingClashes(const sdf::ElementPtr &e, Messages &out) {
  if (!sdf::shouldValidateElement(e)) return;
  for (const auto &[name, count] : e->CountNamedElements())
    if (count > 1)
      out.push_back("non-unique name \"" + name + "\" used by " + std::to_string(count) +
                    " children of " + label(e));
  for (auto c = e->GetFirstElement(); c; c = c->GetNextElement()) siblingClashes(c, out);
}

// The `ign sdf -k` checks after a clean load.
void ignChecks(const sdf::Root &root, Messages &out) {
  const sdf::Root *r = &root;
  const std::vector<std::pair<const char *, bool (*)(const sdf::Root *)>> checks = {
      {"checkCanonicalLinkNames", sdf::checkCanonicalLinkNames},
      {"checkJointParentChildLinkNames", sdf::checkJointParentChildLinkNames},
      {"checkFrameAttachedToGraph", sdf::checkFrameAttachedToGraph},
      {"checkPoseRelativeToGraph", sdf::checkPoseRelativeToGraph},
  };
  for (const auto &[name, check] : checks) {
    std::string said;
    if (!captureCerr(said, [&] { return check(r); }))
      out.push_back(std::string(name) + ": " + (said.empty() ? "failed" : oneLine(said)));
  }
  std::string dump;  // the library dumps whole elements; we name the clash instead
  if (!captureCerr(dump, [&] { return sdf::recursiveSiblingUniqueNames(root.Element()); })) {
    Messages clashes;
    siblingClashes(root.Element(), clashes);
    if (clashes.empty()) clashes.push_back("non-unique sibling names");
    out.insert(out.end(), clashes.begin(), clashes.end());
  }
}

bool needsAxis(sdf::JointType t) {
  using T = sdf::JointType;
  return t == T::REVOLUTE || t == T::PRISMATIC || t == T::GEARBOX || t == T::CONTINUOUS ||
         t == T::REVOLUTE2 || t == T::UNIVERSAL || t == T::SCREW;
}

void lintModel(const sdf::Model &m, Messages &out) {
  const std::string where = "model \"" + m.Name() + "\": ";
  std::map<std::string, std::vector<std::string>> parents;  // child link -> joints
  for (uint64_t j = 0; j < m.JointCount(); ++j) {
    const sdf::Joint &joint = *m.JointByIndex(j);
    const std::string jn = "joint \"" + joint.Name() + "\"";
    parents[joint.ChildLinkName()].push_back(joint.Name());
    const auto elem = joint.Element();
    if (needsAxis(joint.Type()) && !elem->HasElement("axis"))
      out.push_back("lint joint_no_axis: " + where + jn + " of type " +
                    elem->Get<std::string>("type") + " has no <axis>");
    if (joint.Type() == sdf::JointType::FIXED || joint.Type() == sdf::JointType::BALL) continue;
    for (const char *axis : {"axis", "axis2"}) {
      if (!elem->HasElement(axis)) continue;
      auto limit = elem->FindElement(axis)->FindElement("limit");
      if (!limit || !limit->GetExplicitlySetInFile())  // libsdformat fills in +-1e16
        out.push_back("lint axis_no_limit: " + where + jn + " has <" + axis +
                      "> without <limit> (required in SDF 1.6)");
    }
  }
  std::vector<std::string> roots;
  for (uint64_t l = 0; l < m.LinkCount(); ++l) {
    const std::string &name = m.LinkByIndex(l)->Name();
    auto it = parents.find(name);
    if (it == parents.end()) {
      roots.push_back(name);
    } else if (it->second.size() > 1) {
      std::string joints;
      for (const auto &j : it->second) joints += (joints.empty() ? "" : ", ") + j;
      out.push_back("lint multi_parent: " + where + "link \"" + name + "\" is the child of " +
                    std::to_string(it->second.size()) + " joints (" + joints + ")");
    }
  }
  if (roots.size() > 1) {
    std::string names;
    for (const auto &r : roots) names += (names.empty() ? "" : ", ") + r;
    out.push_back("lint disconnected: " + where + std::to_string(roots.size()) +
                  " root links (" + names + ")");
  } else if (roots.empty() && m.LinkCount() > 0) {
    out.push_back("lint disconnected: " + where + "no root link (every link is a joint child)");
  }
  for (uint64_t n = 0; n < m.ModelCount(); ++n) lintModel(*m.ModelByIndex(n), out);
}

void lintRoot(const sdf::Root &root, Messages &out) {
  if (root.Model()) lintModel(*root.Model(), out);
  for (uint64_t w = 0; w < root.WorldCount(); ++w)
    for (uint64_t m = 0; m < root.WorldByIndex(w)->ModelCount(); ++m)
      lintModel(*root.WorldByIndex(w)->ModelByIndex(m), out);
}

Messages checkFile(const std::string &path, bool strict, bool lints) {
  Messages out;
  sdf::Root root;
  std::string console;
  auto errors = captureCerr(console, [&] { return root.Load(path); });
  for (const auto &e : errors) out.push_back(describe(e));
  if (!errors.empty())
    for (const auto &line : consoleLines(console)) out.push_back("parser said: " + line);
  if (lints) lintRoot(root, out);  // on whatever part of the DOM did load
  if (!errors.empty()) return out;  // ign sdf -k stops here too

  if (strict) {
    sdf::ParserConfig config;
    config.SetWarningsPolicy(sdf::EnforcementPolicy::ERR);
    config.SetUnrecognizedElementsPolicy(sdf::EnforcementPolicy::ERR);
    sdf::Root strictRoot;
    auto strictErrors = captureCerr(console, [&] { return strictRoot.Load(path, config); });
    for (const auto &e : strictErrors)
      if (e.Message().find("Element[initial_position], child of element[axis") ==
          std::string::npos)
        out.push_back("strict: " + describe(e));
  }
  ignChecks(root, out);
  return out;
}

}  // namespace

int main(int argc, char **argv) {
  bool strict = false, lints = false;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--strict") strict = true;
    else if (arg == "--lints") lints = true;
    else if (arg.rfind("--", 0) == 0) {
      std::cerr << "usage: sdfcheck [--strict] [--lints] FILE...\n";
      return 2;
    } else files.push_back(arg);
  }
  int failed = 0;
  for (const auto &file : files) {
    const Messages problems = checkFile(file, strict, lints);
    if (problems.empty()) std::cout << "OK " << file << "\n";
    for (const auto &p : problems) std::cout << "ERROR " << file << ": " << p << "\n";
    failed += !problems.empty();
  }
  return failed == 0 ? 0 : 1;
}
