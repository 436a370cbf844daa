"""The Python face of cshapes._cshapes: each public function of the extension wrapped in a Python function
with an explicit signature, numpy-style documentation, one-line answers to misuse, and progress reports.

Where each part comes from (declared once, derived here):

- the signature (every parameter, its kind and default): the type stub cshapes/_cshapes.pyi, which
  tests/python/test_stubs.py holds to the extension (every keyword it reads, each default its own), and whose
  canonical-form block scripts/make_stub.py writes from the methods' option declarations;
- the canonical-form keywords' descriptions, types, limits and choices: those declarations themselves
  (pipeline/method_options.h, via cshapes._cshapes.method_options()), the ones `cshapes canon --help` shows,
  with the CLI's spellings (``--step-rule fixed``) turned into keywords (``step_rule='fixed'``);
- the keywords a function shares with a CLI option (icp()'s trim is `cshapes align --trim`, every
  experiment's resample is `--resample`): their descriptions, limits and choices from the options' own
  declarations in the library (support/option_declaration.h, via cshapes._cshapes.option_declarations()),
  the text `--help` shows, with other options named as Python names them;
- every other parameter's description and each function's prose: cshapes/_docs.py.

A call passes on only what was given (never the defaults), so the extension still tells "given" from "left
out" (fixed_step needs step_rule='fixed') and refuses an old keyword naming the new one.
"""
import ast
import inspect
import re
import sys
import time
from pathlib import Path

from . import _cshapes
from ._docs import COMMON, DOCS

STUB = Path(__file__).with_name("_cshapes.pyi")

# --------------------------------------------------------------------------------------------------------
# Progress


class ProgressBar:
    """progress=True: one line on stderr, rewritten in place, as the CLI prints its stages:
    ``[coulomb]  42.0% (about 12 s left)``, then ``[coulomb] 100.0% in 3.41 s`` and a new line."""

    def __init__(self, stream=None, delay=0.0):
        """delay: seconds of the call before the bar shows (a call done sooner prints nothing)."""
        self.stream = stream if stream is not None else sys.stderr
        self.stage = None
        self.start = self.created = time.monotonic()
        self.delay = delay
        self.width = 0  # of the line written last, so a shorter one leaves no tail

    def __call__(self, stage, fraction, seconds_left):
        now = time.monotonic()
        if now - self.created < self.delay:
            return
        if stage != self.stage:
            if self.width:
                self.stream.write("\n")
            self.stage, self.start, self.width = stage, now, 0
        text = f"[{stage}] {100 * fraction:5.1f}%"
        if fraction >= 1:
            text += f" in {_seconds_text(now - self.start)}"
        elif seconds_left is not None:
            text += f" (about {seconds_left:.0f} s left)"
        self.stream.write("\r" + text.ljust(self.width))
        self.width = len(text)
        if fraction >= 1:
            self.stream.write("\n")
            self.width = 0
        self.stream.flush()

    def close(self):
        """Ends a line left open (a call stopped by an error or Ctrl-C)."""
        if self.width:
            self.stream.write("\n")
            self.stream.flush()
            self.width = 0


def _seconds_text(s):
    """As support/format.h: seconds_text: three significant figures, whole seconds from 1,000 s on."""
    return f"{s:.0f} s" if s >= 1000 else f"{s:.3g} s"


# progress=None on a terminal: the bar of the calls that take longer than this (a quick call prints nothing).
DEFAULT_BAR_DELAY = 1.0


def _progress_callback(progress):
    """progress= as the extension takes it: None (no reports) or a callable; and the bar to close after."""
    if progress is None:
        stream = sys.stderr
        if stream is not None and hasattr(stream, "isatty") and stream.isatty():
            bar = ProgressBar(delay=DEFAULT_BAR_DELAY)
            return bar, bar
        return None, None
    if progress is True:
        bar = ProgressBar()
        return bar, bar
    if progress is False:
        return None, None
    return progress, None  # a callable, or anything else for the extension to refuse by name


# --------------------------------------------------------------------------------------------------------
# Signatures, from the stub


class _Annotation:
    """An annotation shown as the stub writes it (``int``, ``Literal['heat', 'fmm']``), not as a string."""

    def __init__(self, text):
        self.text = text

    def __repr__(self):
        return self.text


def _stub_tree():
    return ast.parse(STUB.read_text(encoding="utf-8"))


def _aliases(tree):
    """The stub's type aliases (``_Path = str | PathLike[str]``): short ones are shown expanded, long ones by
    their name without the underscore (``Methods``), which the Parameters section explains."""
    out = {"_Array": "ArrayLike", "_Path": "str | PathLike", "_Progress": "bool | Callable | None"}
    for node in tree.body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            name = node.targets[0].id
            if name.startswith("_") and name not in out:
                text = ast.unparse(node.value)
                out[name] = text if len(text) <= 60 else name.lstrip("_")
    return out


def _annotation_text(node, aliases):
    if node is None:
        return None
    text = ast.unparse(node)
    for alias in sorted(aliases, key=len, reverse=True):
        text = re.sub(rf"\b{re.escape(alias)}\b", aliases[alias], text)
    return text


def _literal(node):
    return ast.literal_eval(node)


def _parameters(definition, aliases):
    """[inspect.Parameter] of one stub function."""
    a = definition.args
    out = []
    positional = a.posonlyargs + a.args
    defaults = [inspect.Parameter.empty] * (len(positional) - len(a.defaults)) + [_literal(d) for d in a.defaults]
    for k, (arg, default) in enumerate(zip(positional, defaults)):
        kind = (inspect.Parameter.POSITIONAL_ONLY if k < len(a.posonlyargs)
                else inspect.Parameter.POSITIONAL_OR_KEYWORD)
        out.append(inspect.Parameter(arg.arg, kind, default=default,
                                     annotation=_Annotation(_annotation_text(arg.annotation, aliases))))
    for arg, default in zip(a.kwonlyargs, a.kw_defaults):
        out.append(inspect.Parameter(arg.arg, inspect.Parameter.KEYWORD_ONLY,
                                     default=inspect.Parameter.empty if default is None else _literal(default),
                                     annotation=_Annotation(_annotation_text(arg.annotation, aliases))))
    if a.vararg:
        out.append(inspect.Parameter(a.vararg.arg, inspect.Parameter.VAR_POSITIONAL))
    if a.kwarg:
        out.append(inspect.Parameter(a.kwarg.arg, inspect.Parameter.VAR_KEYWORD,
                                     annotation=_Annotation(_annotation_text(a.kwarg.annotation, aliases))))
    return out


def stub_signatures():
    """{name: (inspect.Signature, {keyword: {overload's kind: default}})} of every function of the stub. Overloads
    (generate's, one per kind) merge into one signature: a keyword whose default differs between them defaults
    to None (the kind's own), and the second item gives each kind's default for the documentation."""
    tree = _stub_tree()
    aliases = _aliases(tree)
    definitions = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            definitions.setdefault(node.name, []).append(node)
    out = {}
    for name, defs in definitions.items():
        returns = _Annotation(_annotation_text(defs[0].returns, aliases))
        if len(defs) == 1:
            out[name] = (inspect.Signature(_parameters(defs[0], aliases), return_annotation=returns), {})
            continue
        merged, per_kind, annotations = {}, {}, {}
        head = None
        for d in defs:
            params = _parameters(d, aliases)
            head = head or params[0]
            kind = ast.literal_eval(d.args.args[0].annotation.slice)
            for p in params[1:]:
                per_kind.setdefault(p.name, {})[kind] = p.default
                annotations.setdefault(p.name, set()).add(repr(p.annotation))
                merged.setdefault(p.name, p)
        params = [inspect.Parameter(head.name, head.kind, annotation=_Annotation("str"))]
        for p in merged.values():
            defaults = set(map(repr, per_kind[p.name].values()))
            shared = len(defaults) == 1  # one default wherever it is read (seed=0): shown as it is
            annotation = " | ".join(sorted(annotations[p.name]))
            params.append(p.replace(default=p.default if shared else None,
                                    annotation=_Annotation(annotation if shared else annotation + " | None")))
        out[name] = (inspect.Signature(params, return_annotation=_Annotation(" | ".join(
            sorted({_annotation_text(d.returns, aliases) for d in defs})))), per_kind)
    return out


# --------------------------------------------------------------------------------------------------------
# The methods' options, as their declarations describe them


def _keyword_text(text, flags, choices):
    """A declaration's help with the CLI's spellings turned into keywords: "--step-rule fixed" →
    "step_rule='fixed'", "--mds-solver landmarks|auto" → "mds_solver='landmarks'|'auto'", "--basis" →
    "basis"; "see --help-all" (a CLI screen) dropped."""
    text = re.sub(r"[:;,]? see --help-all", "", text)

    def keyword(m):
        flag, value = m.group(1), m.group(2)
        name = flags.get("--" + flag, flag.replace("-", "_"))
        values = value.split("|") if value else []
        if values and all(v in choices.get(name, ()) for v in values):
            return name + "=" + "|".join(f"'{v}'" for v in values)
        return name + (" " + value if value else "")

    return re.sub(r"--([a-z][a-z0-9-]*)(?: ([a-z][a-z0-9|-]*))?", keyword, text)


def _method_options():
    options = _cshapes.method_options()
    flags = {o["flag"]: o["name"] for o in options}
    choices = {o["name"]: o["choices"] for o in options}
    out = {}
    for o in options:
        help_text = _keyword_text(o["help"], flags, choices)
        first = re.match(r"[A-Za-z_-]*", help_text).group(0)
        if len(first) > 1 and first not in o["choices"]:  # a sentence, not a value ("paper: ...") or a symbol
            help_text = help_text[0].upper() + help_text[1:]
        if not help_text.endswith("."):
            help_text += "."
        if o["limit"]:
            help_text += f" Limit: {o['limit']}."
        out[o["name"]] = dict(o, text=help_text)
    return out


def _sentence(text, choices=()):
    """A help phrase as a docstring's sentence: capitalised (unless it begins with a value, "heat (ours...)"
    or a symbol) and ended by a full stop."""
    first = re.match(r"[A-Za-z_-]*", text).group(0)
    if (len(first) > 1 or first == "a") and first not in choices:
        text = text[0].upper() + text[1:]
    return text if text.endswith(".") else text + "."


def declared_options():
    """{function: {keyword: declaration}} of the keywords each function shares with a CLI option, each with its
    docstring text (the declaration's help, then its limit in words)."""
    out = {}
    for function, declarations in _cshapes.option_declarations().items():
        for o in declarations:
            text = _sentence(o["help"], o["choices"])
            if o["limit"]:
                text += f" Limit: {o['limit']}."
            out.setdefault(function, {})[o["keyword"]] = dict(o, text=text)
    return out


# --------------------------------------------------------------------------------------------------------
# numpy-style docstrings


def _type_text(parameter, option=None):
    """The type line's type: ``int``, ``float``, ``{'heat', 'fmm'}``, ``array_like``, ``str or None``."""
    if option is not None:
        if option["choices"]:
            return "{" + ", ".join(repr(c) for c in option["choices"]) + "}"
        return option["type"]
    text = repr(parameter.annotation) if parameter.annotation is not inspect.Parameter.empty else ""
    literal = re.fullmatch(r"Literal\[(.*)\]( \| None)?", text)
    if literal:
        return "{" + literal.group(1).replace('"', "'") + "}" + (" or None" if literal.group(2) else "")
    text = text.replace("ArrayLike", "array_like").replace("str | PathLike", "path").replace("Callable", "callable")
    parts, depth, part = [], 0, ""
    for c in text:  # split at the top level's " | " only (not inside Callable[[..., float | None], ...])
        depth += (c == "[") - (c == "]")
        part += c
        if depth == 0 and part.endswith(" | "):
            parts.append(part[:-3])
            part = ""
    parts.append(part)
    return " or ".join(p.strip() for p in parts) if text else "object"


def _default_text(parameter, per_kind=None):
    if parameter.kind is inspect.Parameter.VAR_KEYWORD:
        return ""
    if per_kind:
        shared = len(set(map(repr, per_kind.values()))) == 1
        if not shared:
            return ", default: the kind's (" + ", ".join(f"{k}: {v!r}" for k, v in per_kind.items()) + ")"
    if parameter.default is inspect.Parameter.empty:
        return ""
    return f", default {parameter.default!r}"


def _wrap_lines(text, indent="    ", width=100):
    import textwrap
    out = []
    for paragraph in text.split("\n"):
        out += textwrap.wrap(paragraph, width=width, initial_indent=indent, subsequent_indent=indent,
                             break_on_hyphens=False, break_long_words=False) or [""]
    return out


def _section(title, body):
    lines = [title, "-" * len(title)]
    for entry in body.split("\n"):
        if entry.startswith("    "):
            lines += _wrap_lines(entry.strip())
        else:
            lines.append(entry)
    return lines


def render_doc(name, signature, per_kind, options, readers, declared=None):
    """The numpy-style docstring of function `name`; declared: its keywords that have a CLI counterpart
    (declared_options()[name])."""
    declared = declared or {}
    doc = DOCS.get(name, {})
    params = doc.get("params", {})
    lines = _wrap_lines(doc.get("summary", name + "."), indent="")
    if doc.get("description"):
        lines += [""] + _wrap_lines(doc["description"], indent="")
    entries = []
    for p in signature.parameters.values():
        # A method's option, unless this function takes the keyword its own way (smacof's weights: an array).
        own = p.name in params
        # The experiments' geodesics is the MDS methods' option (`cshapes experiment ... --geodesics`).
        method_keyword = name in ("coulomb", "canonical_form", "smacof") or (
            name.startswith("experiment_") and p.name == "geodesics")
        option = options.get(p.name) if method_keyword and not own else None
        if p.name in declared:
            text = declared[p.name]["text"]
        elif own:
            text = params[p.name]
        elif option is not None:
            text = option["text"]
            if name == "canonical_form" and p.name in readers:
                text += " Read by: " + ", ".join(readers[p.name]) + "."
        elif p.name in COMMON:
            text = COMMON[p.name]
        else:
            raise AssertionError(f"{name}(): parameter {p.name} has no description (cshapes/_api.py)")
        if per_kind.get(p.name) and len(per_kind[p.name]) < len(set().union(*map(set, per_kind.values()))):
            text += " Kinds: " + ", ".join(per_kind[p.name]) + "."
        head = ("**" if p.kind is inspect.Parameter.VAR_KEYWORD else "") + p.name
        entries.append(f"{head} : {_type_text(p, option)}{_default_text(p, per_kind.get(p.name))}")
        entries += _wrap_lines(text)
    if entries:
        lines += ["", "Parameters", "----------"] + entries
    if name == "canonical_form":  # the methods, each with the keywords it reads, from their registrations
        all_options = _cshapes.method_options()
        flags = {o["flag"]: o["name"] for o in all_options}
        choices = {o["name"]: o["choices"] for o in all_options}
        notes = "\n".join(f"method={m['name']!r}\n    {_keyword_text(m['summary'], flags, choices).rstrip('.')}. "
                          f"Keywords: {', '.join(m['keywords'] + ['knn', 'strict'])}."
                          for m in _cshapes.canonical_form_methods())
        doc = dict(doc, notes=notes)
    for title, key in (("Returns", "returns"), ("Raises", "raises"), ("Notes", "notes"), ("Examples", "examples")):
        if doc.get(key):
            lines += [""] + (_section(title, doc[key]) if key != "examples" else [title, "-" * len(title)] +
                             doc[key].split("\n"))
    return "\n".join(lines)


# --------------------------------------------------------------------------------------------------------
# The wrappers


def _shown(value):
    """An argument as a one-line message shows it: arrays by shape and dtype, never their values."""
    shape = getattr(value, "shape", None)
    if shape is not None and hasattr(value, "dtype"):
        return f"<array {tuple(shape)} {value.dtype}>"
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _wrap(name, extension, signature, doc):
    parameters = list(signature.parameters.values())
    positional = [p for p in parameters if p.kind in (inspect.Parameter.POSITIONAL_ONLY,
                                                      inspect.Parameter.POSITIONAL_OR_KEYWORD)]
    keyword_only = [p for p in parameters if p.kind is inspect.Parameter.KEYWORD_ONLY]
    takes_progress = "progress" in signature.parameters

    def too_many(args):
        names = ", ".join(p.name for p in positional)
        extra = args[len(positional):]
        hint = ", ".join(f"{p.name}={_shown(v)}" for p, v in zip(keyword_only, extra))
        given = f"{len(args)} {'was' if len(args) == 1 else 'were'} given"
        return (f"{name}() takes {len(positional)} positional argument{'s' if len(positional) != 1 else ''} "
                f"({names}) but {given}" + (f"; options are keywords: {hint}" if hint else ""))

    def function(*args, **kwargs):
        if len(args) > len(positional):
            raise TypeError(too_many(args)) from None
        for p in positional[:len(args)]:
            if p.name in kwargs:
                raise TypeError(f"{name}() got multiple values for argument '{p.name}'")
        missing = [p.name for p in positional[len(args):]
                   if p.default is inspect.Parameter.empty and p.name not in kwargs]
        missing += [p.name for p in keyword_only if p.default is inspect.Parameter.empty and p.name not in kwargs]
        if missing:
            raise TypeError(f"{name}() missing {len(missing)} required argument{'s' if len(missing) > 1 else ''}: "
                            + ", ".join(f"'{m}'" for m in missing))
        bar = None
        if takes_progress:
            kwargs["progress"], bar = _progress_callback(kwargs.get("progress"))
            if kwargs["progress"] is None:
                del kwargs["progress"]
        try:
            return extension(*args, **kwargs)
        except TypeError as e:
            if "incompatible function arguments" not in str(e):
                raise
            given = [f"{p.name}={_shown(v)}" for p, v in zip(positional, args)]
            given += [f"{k}={_shown(v)}" for k, v in kwargs.items() if k != "progress"]
            expected = ", ".join(f"{p.name}: {_type_text(p)}" for p in positional + keyword_only
                                 if p.name in {g.split('=')[0] for g in given})
            raise TypeError(f"{name}(): an argument of the wrong type: got {', '.join(given)}; expected "
                            f"{expected}") from None
        finally:
            if bar is not None:
                bar.close()

    function.__name__ = function.__qualname__ = name
    function.__module__ = "cshapes"
    function.__doc__ = doc
    function.__signature__ = signature
    function.__wrapped__ = extension
    return function


def _with_method_options(name, signature, options):
    """coulomb()'s and canonical_form()'s signature with the methods' options straight from their
    declarations (a module built with another method, as tests/toy_method's, shows that method's keywords
    too); the other parameters (V, F, method, knn, strict, ...) as the stub gives them."""
    if name == "coulomb":
        names = next(m["keywords"] for m in _cshapes.canonical_form_methods() if m["name"] == "coulomb")
    else:
        names = list(options)
    params = [p for p in signature.parameters.values() if p.kind is not inspect.Parameter.KEYWORD_ONLY]
    if "method" in signature.parameters:
        params.append(signature.parameters["method"])
    for n in names:
        o = options[n]
        annotation = ("Literal[" + ", ".join(repr(c) for c in o["choices"]) + "]") if o["choices"] else o["type"]
        params.append(inspect.Parameter(n, inspect.Parameter.KEYWORD_ONLY, default=o["default"],
                                        annotation=_Annotation(annotation)))
    params += [p for p in signature.parameters.values() if p.kind is inspect.Parameter.KEYWORD_ONLY
               and p.name != "method" and p.name not in options]
    return signature.replace(parameters=params)


def wrapped_functions():
    """{name: the Python function} for every function of the stub."""
    signatures = stub_signatures()
    options = _method_options()
    for name in ("coulomb", "canonical_form"):
        signatures[name] = (_with_method_options(name, signatures[name][0], options), {})
    readers = {n: o["methods"] for n, o in options.items()}
    declared = declared_options()
    out = {}
    for name, (signature, per_kind) in signatures.items():
        extension = getattr(_cshapes, name)
        out[name] = _wrap(name, extension, signature,
                          render_doc(name, signature, per_kind, options, readers, declared.get(name)))
    return out
