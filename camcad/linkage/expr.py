"""A safe expression language for ``camcad linkage fgen --function``: y = f(x), no eval.

A small recursive-descent parser builds a tree of numbers, the variable ``x``, the constants ``pi``
and ``e``, the operators + − * / and ^ (or **, right-associative, binding tighter than unary minus:
-x^2 = −(x²)), parentheses and calls of a fixed list of functions. Anything else — other names,
attributes, strings, brackets, commas outside a call — is refused with the position of the offending
character. Nothing of the user's text ever reaches Python's ``eval``.

The tree evaluates on numpy arrays, real or complex; complex arguments give the complex-step
derivative f'(x) = Im f(x + ih)/h (Squire & Trapp, SIAM Review 40 (1998) 110–112), exact to
rounding for the analytic functions of the list (``abs`` is not analytic: a central difference is
used instead when it appears).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camcad.errors import CamcadError

FUNCTIONS = {
    "sin": np.sin, "cos": np.cos, "tan": np.tan, "asin": np.arcsin, "acos": np.arccos, "atan": np.arctan,
    "sinh": np.sinh, "cosh": np.cosh, "tanh": np.tanh, "exp": np.exp, "log": np.log, "ln": np.log,
    "log10": np.log10, "log2": np.log2, "sqrt": np.sqrt, "abs": np.abs,
}
CONSTANTS = {"pi": np.pi, "e": np.e}
MAX_LENGTH = 400
MAX_DEPTH = 40
WHERE = "--function"


@dataclass(frozen=True)
class _Token:
    kind: str      # num, name, op, lpar, rpar, end
    text: str
    pos: int       # 1-based column


def _error(text: str, pos: int, what: str, fix: str) -> CamcadError:
    return CamcadError(f"{what} at position {pos} of {text!r}", WHERE, fix)


#: the digits of a number: ASCII only ("²" or "١" are not numbers here, and reach the parser as bad characters)
_DIGITS = frozenset("0123456789")


def _tokens(text: str) -> list[_Token]:
    out = []
    i = 0
    while i < len(text):
        ch = text[i]
        if ch.isspace():
            i += 1
            continue
        start = i
        if ch in _DIGITS or (ch == "." and i + 1 < len(text) and text[i + 1] in _DIGITS):
            while i < len(text) and (text[i] in _DIGITS or text[i] == "."):
                i += 1
            if i < len(text) and text[i] in "eE":
                j = i + 1
                if j < len(text) and text[j] in "+-":
                    j += 1
                if j < len(text) and text[j] in _DIGITS:
                    i = j
                    while i < len(text) and text[i] in _DIGITS:
                        i += 1
            literal = text[start:i]
            if literal.count(".") > 1:
                raise _error(text, start + 1, f"malformed number {literal!r}", "write numbers like 2, 0.5 or 1e-3")
            out.append(_Token("num", literal, start + 1))
            continue
        if ch.isascii() and (ch.isalpha() or ch == "_"):
            while i < len(text) and text[i].isascii() and (text[i].isalnum() or text[i] == "_"):
                i += 1
            out.append(_Token("name", text[start:i], start + 1))
            continue
        if text.startswith("**", i):
            out.append(_Token("op", "^", start + 1))
            i += 2
            continue
        if ch in "+-*/^":
            out.append(_Token("op", ch, start + 1))
        elif ch == "(":
            out.append(_Token("lpar", ch, start + 1))
        elif ch == ")":
            out.append(_Token("rpar", ch, start + 1))
        else:
            out.append(_Token("bad", ch, start + 1))  # refused when the parser reaches it
        i += 1
    out.append(_Token("end", "", len(text) + 1))
    return out


class _Parser:
    def __init__(self, text: str):
        self.text = text
        self.tokens = _tokens(text)
        self.k = 0
        self.depth = 0
        self.uses_abs = False

    def peek(self) -> _Token:
        return self.tokens[self.k]

    def take(self) -> _Token:
        token = self.tokens[self.k]
        if token.kind == "bad":
            raise _error(self.text, token.pos, f"character {token.text!r} is not allowed",
                         "use numbers, x, pi, e, + - * / ^, parentheses and the functions "
                         + ", ".join(sorted(FUNCTIONS)))
        self.k += 1
        return token

    def enter(self, token: _Token) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise _error(self.text, token.pos, f"nesting deeper than {MAX_DEPTH}", "simplify the expression")

    def parse(self):
        tree = self.expr()
        token = self.peek()
        if token.kind != "end":
            raise _error(self.text, token.pos, f"unexpected {token.text!r}", "check the operators and parentheses")
        return tree

    def expr(self):
        node = self.term()
        while self.peek().kind == "op" and self.peek().text in "+-":
            op = self.take().text
            node = (op, node, self.term())
        return node

    def term(self):
        node = self.unary()
        while self.peek().kind == "op" and self.peek().text in "*/":
            op = self.take().text
            node = (op, node, self.unary())
        return node

    def unary(self):
        token = self.peek()
        if token.kind == "op" and token.text in "+-":
            self.take()
            self.enter(token)
            operand = self.unary()
            self.depth -= 1
            return ("neg", operand) if token.text == "-" else operand
        return self.power()

    def power(self):
        base = self.atom()
        if self.peek().kind == "op" and self.peek().text == "^":
            token = self.take()
            self.enter(token)
            exponent = self.unary()
            self.depth -= 1
            return ("^", base, exponent)
        return base

    def atom(self):
        token = self.take()
        if token.kind == "num":
            return ("num", float(token.text))
        if token.kind == "lpar":
            self.enter(token)
            node = self.expr()
            self.depth -= 1
            close = self.take()
            if close.kind != "rpar":
                raise _error(self.text, close.pos,
                             "missing ')'" if close.kind == "end" else f"unexpected {close.text!r}",
                             f"close the '(' opened at position {token.pos}")
            return node
        if token.kind == "name":
            name = token.text
            if name == "x":
                return ("x",)
            if name in CONSTANTS:
                return ("num", float(CONSTANTS[name]))
            if name in FUNCTIONS:
                open_ = self.take()
                if open_.kind != "lpar":
                    raise _error(self.text, open_.pos, f"function {name} needs '(' after its name",
                                 f"write {name}(x)")
                self.enter(token)
                argument = self.expr()
                self.depth -= 1
                close = self.take()
                if close.kind != "rpar":
                    raise _error(self.text, close.pos,
                                 "missing ')'" if close.kind == "end" else f"unexpected {close.text!r}",
                                 f"{name} takes one argument: {name}(...)")
                if name == "abs":
                    self.uses_abs = True
                return ("call", name, argument)
            raise _error(self.text, token.pos, f"unknown name {name!r}",
                         "the variable is x; constants pi, e; functions " + ", ".join(sorted(FUNCTIONS)))
        if token.kind == "end":
            raise _error(self.text, token.pos, "the expression ends too early", "complete the expression")
        raise _error(self.text, token.pos, f"unexpected {token.text!r}", "check the operators and parentheses")


def _evaluate(node, x):
    kind = node[0]
    if kind == "num":
        return node[1] + 0 * x
    if kind == "x":
        return x
    if kind == "neg":
        return -_evaluate(node[1], x)
    if kind == "call":
        return FUNCTIONS[node[1]](_evaluate(node[2], x))
    left, right = _evaluate(node[1], x), _evaluate(node[2], x)
    if kind == "+":
        return left + right
    if kind == "-":
        return left - right
    if kind == "*":
        return left * right
    if kind == "/":
        return left / right
    return left ** right


@dataclass(frozen=True)
class Expression:
    """A parsed ``--function``: call it on an array of x; ``derivative`` gives f'(x)."""

    text: str
    tree: tuple
    analytic: bool

    def __call__(self, x):
        x = np.asarray(x, dtype=float)
        with np.errstate(all="ignore"):
            y = _evaluate(self.tree, x)
        return np.asarray(y, dtype=float) if not np.iscomplexobj(y) else np.asarray(y.real, dtype=float)

    def derivative(self, x):
        """f'(x): complex step (h = 1e-30, exact to rounding) when the expression is analytic,
        else a 4th-order central difference."""
        x = np.asarray(x, dtype=float)
        with np.errstate(all="ignore"):
            if self.analytic:
                h = 1e-30
                return np.asarray(np.imag(_evaluate(self.tree, x + 1j * h)) / h, dtype=float)
            h = 1e-4 * np.maximum(1.0, np.abs(x))

            def f(t):
                return np.asarray(_evaluate(self.tree, t), dtype=float)

            return (f(x - 2 * h) - 8 * f(x - h) + 8 * f(x + h) - f(x + 2 * h)) / (12 * h)


def parse_expression(text: str) -> Expression:
    """Parse ``text`` (a function of x) into an ``Expression``; a ``CamcadError`` naming the position
    of the first problem otherwise.

    Parameters
    ----------
    text : str
        e.g. ``"log10(x)"``, ``"x^2 + 1"``, ``"sin(pi*x/2)"``.

    Returns
    -------
    Expression
        Callable on numpy arrays.

    Examples
    --------
    >>> f = parse_expression("log10(x)")
    >>> float(f(100.0))
    2.0
    >>> round(float(f.derivative(1.0)), 15) == round(1 / 2.302585092994046, 15)
    True
    >>> float(parse_expression("-2^2")(0.0)), float(parse_expression("2^3^2")(0.0))
    (-4.0, 512.0)
    >>> parse_expression("__import__('os')")
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: --function: unknown name '__import__' at position 1 of "__import__('os')"; ...
    """
    if not isinstance(text, str) or not text.strip():
        raise CamcadError("the function is empty", WHERE, 'give an expression in x, e.g. --function "log10(x)"')
    if len(text) > MAX_LENGTH:
        raise CamcadError(f"the function is {len(text)} characters long, more than {MAX_LENGTH}", WHERE,
                          "shorten it or give the function as --table")
    parser = _Parser(text)
    tree = parser.parse()
    return Expression(text, tree, not parser.uses_abs)
