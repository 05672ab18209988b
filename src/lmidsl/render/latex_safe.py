r"""TeX that reads and writes nothing: the user's strings in a document, and its last check.

Names, labels, ids and LaTeX names come from the user (a theorem file, a quick-mode spec, a
command line).  TeX is a programming language with file input and output (``\input``,
``\openin``, ``\write``, ``\includegraphics``) and with ways of building a command from letters
(``\csname``, ``^^5c``, ``\scantokens``, catcodes, expl3's ``\use:c``), so no user string is
written as it is:

* :func:`math_name` escapes any string for maths (``A\input{x}`` prints as
  ``\mathrm{A\backslash{}input\{x\}}``);
* :func:`safe_math` keeps a declared LaTeX name (``\hat{A}_f``, ``\bar{\xi}_1``) when it is
  written in a small language of known, harmless control words with balanced braces, and else
  prints it escaped (a LaTeX name is notation, never a program);
* :func:`guarded` is the last check of a whole document body: any control word that reads or
  writes a file, defines a command or changes how TeX reads (:data:`FORBIDDEN`), and ``^^``, are
  made inert (``\string\input`` prints the characters and does nothing), whatever path wrote them.

pdflatex itself runs without shell escape and with kpathsea's paranoid ``openin_any=p`` /
``openout_any=p`` in a fresh folder (:mod:`lmidsl.cli.latex_cmd`): the third wall.
"""
from __future__ import annotations

import re

from .latex_text import _GREEK, _char_text, _greek_of

#: control words that read or write files, define or copy commands, change category codes or
#: build a control sequence from characters; also everything of LaTeX3's syntax switch
FORBIDDEN = frozenset("""
input include includeonly InputIfFileExists IfFileExists openin openout read readline write immediate
closein closeout newread newwrite special catcode lccode uccode sfcode mathcode delcode def edef gdef
xdef let futurelet csname endcsname begincsname ifcsname lastnamedcs expandafter scantokens
newcommand renewcommand providecommand DeclareRobustCommand NewDocumentCommand RenewDocumentCommand
ProvideDocumentCommand DeclareDocumentCommand NewDocumentEnvironment RenewDocumentEnvironment
NewCommandCopy RenewCommandCopy DeclareCommandCopy NewEnvironmentCopy UseName ExpandArgs ExplSyntaxOn
ExplSyntaxOff makeatletter makeatother newenvironment renewenvironment usepackage RequirePackage
documentclass LoadClass includegraphics includepdf lstinputlisting verbatiminput everyjob everypar
everymath everydisplay everyhbox everyvbox everycr everyeof output shipout endinput dump errhelp
pdfximage pdfrefximage pdfobj pdfrefobj pdffiledump pdfmdfivesum pdffilesize pdffilemoddate
pdfinclusion pdfannot pdfliteral pdfcatalog pdfnames pdfstartlink directlua latelua luaexec
openimage tracingonline jobname pdfprimitive primitive pdfstrcmp pdfescapestring pdfshellescape
""".split())

_CONTROL = re.compile(r"\\([A-Za-z]+|.)", re.S)
_FILECONTENTS = re.compile(r"\\begin\s*\{\s*filecontents")

#: control words a declared LaTeX name may use: Greek, accents, fonts, a few symbols and spaces
_SAFE_WORDS = frozenset(_GREEK | {
    "varepsilon", "vartheta", "varphi", "varrho", "varsigma", "varpi", "varkappa", "epsilon",
    "hat", "bar", "tilde", "check", "dot", "ddot", "dddot", "vec", "breve", "acute", "grave", "mathring",
    "widehat", "widetilde", "overline", "underline", "overrightarrow", "mathrm", "mathbf", "mathit",
    "mathsf", "mathtt", "mathcal", "mathbb", "mathfrak", "mathscr", "boldsymbol", "bm", "operatorname",
    "text", "textrm", "textit", "textbf", "star", "ast", "prime", "top", "intercal", "dagger",
    "ddagger", "infty", "partial", "nabla", "ell", "hbar", "imath", "jmath", "cdot", "cdots", "ldots",
    "dots", "times", "otimes", "oplus", "circ", "bullet", "quad", "qquad", "left", "right", "big", "Big",
    "langle", "rangle", "lvert", "rvert", "lVert", "rVert", "vert", "Vert", "frac", "tfrac", "dfrac",
    "sqrt", "min", "max", "inf", "sup", "lim", "log", "exp", "det", "tr", "sum", "prod", "star",
    "backslash", "mathcal", "natural", "sharp", "flat", "diamond", "triangle", "square", "lozenge",
})
#: control symbols a declared LaTeX name may use: spaces, escaped specials
_SAFE_SYMBOLS = frozenset(",;:! {}_|%#&$")

#: characters written escaped in maths (inside \mathrm{...})
_MATH_ESCAPES = {"\\": r"\backslash{}", "{": r"\{", "}": r"\}", "_": r"\_", "^": r"\wedge{}",
                 "%": r"\%", "#": r"\#", "&": r"\&", "$": r"\$", "~": r"\sim{}", " ": r"\ "}


def math_text(text: str) -> str:
    """Any string as characters in maths mode (for ``\\mathrm{...}``): specials escaped, a
    non-ASCII letter as its Greek command or its code point."""
    out = []
    for ch in str(text):
        if ch in _MATH_ESCAPES:
            out.append(_MATH_ESCAPES[ch])
        elif ch.isascii() and ch.isprintable():
            out.append(ch)
        else:
            greek = _greek_of(ch)
            out.append(greek + "{}" if greek else f"[U+{ord(ch):04X}]")
    return "".join(out)


def plain_text(text: str) -> str:
    """Any string as LaTeX text, character by character (specials escaped, Unicode maths as
    maths; no code-like spans recognised, unlike :func:`~lmidsl.render.latex_text.tex_text`)."""
    return _char_text(" ".join(str(text).split()))


def math_name(text: str) -> str:
    r"""An identifier of unknown content as maths: ``\mathrm{...}`` of its escaped characters."""
    return rf"\mathrm{{{math_text(text)}}}"


def is_safe_math(latex: str) -> bool:
    """Whether a LaTeX fragment uses only :data:`_SAFE_WORDS`, :data:`_SAFE_SYMBOLS`, no ``^^``,
    no comment or alignment character, and balanced braces."""
    if "^^" in latex or any(c in latex for c in "%#&$") or not latex.isprintable():
        return False
    for m in _CONTROL.finditer(latex):
        word = m.group(1)
        if len(word) == 1 and not word.isalpha():
            if word not in _SAFE_SYMBOLS:
                return False
        elif word not in _SAFE_WORDS:
            return False
    depth = 0
    for m in re.finditer(r"\\.|[{}]", latex, re.S):
        if m.group() in "{}":
            depth += 1 if m.group() == "{" else -1
            if depth < 0:
                return False
    return depth == 0


def safe_math(latex: str) -> str:
    """A declared LaTeX name as it is when :func:`is_safe_math`, else escaped (:func:`math_name`)."""
    latex = str(latex)
    return latex if is_safe_math(latex) else math_name(latex)


def forbidden_in(text: str) -> list[str]:
    """The forbidden control words (and ``^^``, ``filecontents``) found in ``text`` (one made
    inert by :func:`guarded`, ``\\string\\input``, is not counted)."""
    text = re.sub(r"\\string\\[A-Za-z]+", "", text)
    found = [m.group() for m in _CONTROL.finditer(text) if m.group(1) in FORBIDDEN]
    if "^^" in text:
        found.append("^^")
    if _FILECONTENTS.search(text):
        found.append(r"\begin{filecontents}")
    return found


def guarded(body: str) -> str:
    r"""A document body with every :data:`FORBIDDEN` control word made inert (``\string\word``
    typesets the characters), ``^^`` broken (``^{}^``) and a ``filecontents`` environment
    renamed; a body written by lmidsl's printers from escaped strings is returned unchanged."""
    body = _CONTROL.sub(lambda m: r"\string" + m.group() if m.group(1) in FORBIDDEN else m.group(), body)
    while "^^" in body:
        body = body.replace("^^", "^{}^")
    return _FILECONTENTS.sub(r"\\begin{lmidsl-refused-filecontents", body)
