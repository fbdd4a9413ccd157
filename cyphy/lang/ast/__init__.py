"""The syntax tree of RoboSim model files: frozen dataclasses with source spans.

This is what the parser returns and what name resolution and elaboration read. Member lists
keep source order (the notation's members are unordered and may repeat, and checks need to see
duplicates); properties give the members of one kind. Expressions are :mod:`cyphy.expr` nodes.

The classes live in one module per part of the notation (:mod:`.core`: the base and the
declarations; :mod:`.physical`: p-models; :mod:`.mappings`: platform mappings; :mod:`.dmodel`:
d-models and state machines; :mod:`.files`: a parsed file); every name is re-exported here,
so ``from cyphy.lang import ast`` then ``ast.Block`` reads as before.
"""

from __future__ import annotations

from cyphy.lang.ast.core import (
    Annotation, AnnotationArg, AnnotationTemplate, DataType, DeclKind, EndPackage,
    Enumeration, expressions_in, FunctionDecl, Import, MatrixType, members_of, NamedType, Node,
    PackageDecl, Param, PrimitiveType, QName, SeqType, SetType, TemplateInstance, TemplateParam,
    TypeDecl, TypeRef, UnitDecl, VarDecl, VectorType,
)
from cyphy.lang.ast.dmodel import (
    ClockDecl, Connection, Context, Controller, CycleDef, EventDecl, Interface, InterfaceUse,
    MachineNode, MachineRef, Module, NodeRef, OperationSig, RoboticPlatform, State, StateAction,
    StateMachine, Terminates, Transition,
)
from cyphy.lang.ast.files import (
    ParseResult, SourceFile, TopLevel,
)
from cyphy.lang.ast.mappings import (
    Action, Assign, CallStatement, ClockReset, EventMapping, ExecStatement, MappingMember,
    OperationMapping, PlatformMapping, Predicate, SendStatement, SkipStatement, Statement,
    VariableMapping, WaitStatement,
)
from cyphy.lang.ast.physical import (
    Block, BlockKind, Bounce, Constraint, DefBlock, Definition, DefMember, Equation,
    FixedConnection, FlexibleConnection, Friction, FrictionEntry, GeomArg, IndexDecl,
    InertiaEntry, Inertial, Instantiation, LaserRetro, Mesh, Part, PartFixed, PartFlexible,
    PModel, Pose, PoseField, REF_KINDS, Relation, Shape, Solution, SolutionInput,
)

__all__ = [
    "Annotation", "AnnotationArg", "AnnotationTemplate", "DataType", "DeclKind", "EndPackage",
    "Enumeration", "expressions_in", "FunctionDecl", "Import", "MatrixType", "members_of",
    "NamedType", "Node", "PackageDecl", "Param", "PrimitiveType", "QName", "SeqType", "SetType",
    "TemplateInstance", "TemplateParam", "TypeDecl", "TypeRef", "UnitDecl", "VarDecl",
    "VectorType", "Block", "BlockKind", "Bounce", "Constraint", "DefBlock", "Definition",
    "DefMember", "Equation", "FixedConnection", "FlexibleConnection", "Friction",
    "FrictionEntry", "GeomArg", "IndexDecl", "InertiaEntry", "Inertial", "Instantiation",
    "LaserRetro", "Mesh", "Part", "PartFixed", "PartFlexible", "PModel", "Pose", "PoseField",
    "REF_KINDS", "Relation", "Shape", "Solution", "SolutionInput", "Action", "Assign",
    "CallStatement", "ClockReset", "EventMapping", "ExecStatement", "MappingMember",
    "OperationMapping", "PlatformMapping", "Predicate", "SendStatement", "SkipStatement",
    "Statement", "VariableMapping", "WaitStatement", "ClockDecl", "Connection", "Context",
    "Controller", "CycleDef", "EventDecl", "Interface", "InterfaceUse", "MachineNode",
    "MachineRef", "Module", "NodeRef", "OperationSig", "RoboticPlatform", "State",
    "StateAction", "StateMachine", "Terminates", "Transition", "ParseResult", "SourceFile",
    "TopLevel",
]
