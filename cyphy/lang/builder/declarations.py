"""The rules of files and declarations: packages, imports, constants and variables, types,
functions, data types, units, annotations and their templates."""

from __future__ import annotations

from typing import Any

from lark import Token

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.lang.builder.base import QN, BuilderBase, Tagged, name_of, text_of
from cyphy.lang.reductions import Pos


class DeclarationRules(BuilderBase):
    """Methods of the declaration rules."""

    # ----- files
    def start(self, pos: Pos, children: list[Any]) -> ast.SourceFile:
        return ast.SourceFile(self.path, self._flat(children), span=self._span(pos))

    def package_decl(self, pos: Pos, c: list[Any]) -> ast.PackageDecl:
        return ast.PackageDecl(c[0].parts, span=self._span(pos))

    def endpackage(self, pos: Pos, c: list[Any]) -> ast.EndPackage:
        return ast.EndPackage(span=self._span(pos))

    def import_all(self, pos: Pos, c: list[Any]) -> ast.Import:
        return ast.Import(tuple(name_of(t) for t in c), True, span=self._span(pos))

    def import_one(self, pos: Pos, c: list[Any]) -> ast.Import:
        return ast.Import(tuple(name_of(t) for t in c), False, span=self._span(pos))

    def qname(self, pos: Pos, c: list[Token]) -> QN:
        return QN(tuple(name_of(t) for t in c), self._span(pos))

    # ----- declarations
    def var_decl(self, pos: Pos, c: list[Any]) -> Tagged:
        name, type_, value = c
        return Tagged(name_of(name), (type_, value), self._span(pos))

    def _decls(self, kind: ast.DeclKind, c: list[Tagged]) -> list[ast.VarDecl]:
        return [ast.VarDecl(kind, t.tag, t.value[0], t.value[1], span=t.span) for t in c]

    def const_decls(self, pos: Pos, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.CONST, c)

    def var_decls(self, pos: Pos, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.VAR, c)

    def input_decls(self, pos: Pos, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.INPUT, c)

    def output_decls(self, pos: Pos, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.OUTPUT, c)

    def inout_decls(self, pos: Pos, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.INOUT, c)

    def local_decls(self, pos: Pos, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.LOCAL, c)

    def prim_type(self, pos: Pos, c: list[Token]) -> ast.PrimitiveType:
        return ast.PrimitiveType(text_of(c[0]), span=self._span(pos))

    def vector_type(self, pos: Pos, c: list[Any]) -> ast.VectorType:
        return ast.VectorType(c[0], c[1], span=self._span(pos))

    def matrix_type(self, pos: Pos, c: list[Any]) -> ast.MatrixType:
        return ast.MatrixType(c[0], c[1], c[2], span=self._span(pos))

    def seq_type(self, pos: Pos, c: list[Any]) -> ast.SeqType:
        return ast.SeqType(c[0], span=self._span(pos))

    def set_type(self, pos: Pos, c: list[Any]) -> ast.SetType:
        return ast.SetType(c[0], span=self._span(pos))

    def named_type(self, pos: Pos, c: list[Any]) -> ast.NamedType:
        return ast.NamedType(c[0].parts, span=self._span(pos))

    def type_decl(self, pos: Pos, c: list[Token]) -> ast.TypeDecl:
        return ast.TypeDecl(name_of(c[0]), span=self._span(pos))

    def param(self, pos: Pos, c: list[Any]) -> ast.Param:
        return ast.Param(name_of(c[0]), c[1], span=self._span(pos))

    field = param

    def function_decl(self, pos: Pos, c: list[Any]) -> ast.FunctionDecl:
        name, rest = c[0], self._flat(c[1:])
        params = tuple(x for x in rest if isinstance(x, ast.Param))
        types = [x for x in rest if not isinstance(x, (ast.Param, Tagged))]
        body = [x for x in rest if isinstance(x, Tagged)]
        conditions = body[0].value if body else []
        return ast.FunctionDecl(
            name_of(name),
            params,
            types[0] if types else None,
            tuple(v for k, v in conditions if k == "pre"),
            tuple(v for k, v in conditions if k == "post"),
            span=self._span(pos),
        )

    def function_body(self, pos: Pos, c: list[Any]) -> Tagged:
        return Tagged("body", list(c), self._span(pos))

    def precondition(self, pos: Pos, c: list[Any]) -> tuple[str, ex.Expr]:
        return ("pre", c[0])

    def postcondition(self, pos: Pos, c: list[Any]) -> tuple[str, ex.Expr]:
        return ("post", c[0])

    def datatype(self, pos: Pos, c: list[Any]) -> ast.DataType:
        return ast.DataType(name_of(c[0]), tuple(c[1:]), False, span=self._span(pos))

    def record(self, pos: Pos, c: list[Any]) -> ast.DataType:
        return ast.DataType(name_of(c[0]), tuple(c[1:]), True, span=self._span(pos))

    def enumeration(self, pos: Pos, c: list[Token]) -> ast.Enumeration:
        return ast.Enumeration(name_of(c[0]), tuple(name_of(t) for t in c[1:]), span=self._span(pos))

    def primitive_unit(self, pos: Pos, c: list[Token]) -> ast.UnitDecl:
        return ast.UnitDecl(name_of(c[0]), span=self._span(pos))

    def derived_unit(self, pos: Pos, c: list[Any]) -> ast.UnitDecl:
        return ast.UnitDecl(name_of(c[0]), c[1], c[2], span=self._span(pos))

    # ----- annotations
    def annotation_template(self, pos: Pos, c: list[Any]) -> ast.AnnotationTemplate:
        name, extends, *params = c
        return ast.AnnotationTemplate(
            name_of(name), extends.parts if extends else None, tuple(params), span=self._span(pos)
        )

    def value_param(self, pos: Pos, c: list[Any]) -> ast.TemplateParam:
        # `["=" _ann_value]` inlines its rule, so an absent default leaves no placeholder.
        name, type_, *rest = c
        default = rest[0] if rest else None
        return ast.TemplateParam(name_of(name), type_, None, default, span=self._span(pos))

    def template_param(self, pos: Pos, c: list[Any]) -> ast.TemplateParam:
        name, template, default = c
        return ast.TemplateParam(name_of(name), None, template.parts, default, span=self._span(pos))

    def annotation(self, pos: Pos, c: list[Any]) -> ast.Annotation:
        span = self._span(pos)
        inst = ast.TemplateInstance(c[0].parts, tuple(c[1:]), span=span)
        return ast.Annotation(inst, span=span)

    def ann_inst(self, pos: Pos, c: list[Any]) -> ast.AnnotationArg:
        return ast.AnnotationArg(name_of(c[0]), c[1], span=self._span(pos))

    def template_inst(self, pos: Pos, c: list[Any]) -> ast.TemplateInstance:
        return ast.TemplateInstance(c[0].parts, tuple(c[1:]), span=self._span(pos))

    # ----- p-models and blocks
