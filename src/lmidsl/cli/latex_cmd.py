"""``lmidsl latex``: the theorem as a LaTeX document (and a PDF with ``--pdf``)."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from ..errors import InputError, LmidslError
from ..pipeline import solve
from ..render.latex_document import lmi_snippet, theorem_latex
from ..studies.store import atomic_write_text, check_output_file
from ..theorem.registry import get_example, get_theorem
from .common import add_solve_arguments, instance_spec, print_json, refuse, solve_arguments

ORDER = 40


class PdflatexMissing(LmidslError):
    """pdflatex is not on PATH."""


def register(sub):
    p = sub.add_parser("latex", help="LaTeX document of a theorem's LMIs (optionally solved)")
    add_solve_arguments(p, solver_help="solver for --example, --data or --set (default: clarabel)")
    p.add_argument("-o", "--output", metavar="FILE.tex",
                   help="write the document here (default: stdout; with --pdf: THEOREM.tex)")
    p.add_argument("--pdf", action="store_true", help="also run pdflatex on the document")
    p.add_argument("--lmi", metavar="LABEL",
                   help="print only this LMI's LaTeX, ready to paste (no preamble), e.g. --lmi 30")
    p.add_argument("--star", choices=["star", "asterisk"], default="star",
                   help="symbol for the implicit triangle: \\star (default) or *")
    p.add_argument("--he", choices=["expand", "collapse"], default="expand",
                   help="print X + X^T as is (default) or as He(X)")
    p.add_argument("--relation", choices=["<", "prec"], default="<",
                   help="write M < 0 (default) or M \\prec 0")
    p.set_defaults(run=run)


def compile_pdf(tex_path: Path) -> Path:
    """Run pdflatex on ``tex_path`` in its folder; the PDF path, or a one-line error."""
    exe = shutil.which("pdflatex")
    if exe is None:
        raise PdflatexMissing(
            f"--pdf: pdflatex is not installed (apt-get install texlive-latex-base); "
            f"the LaTeX source is in {tex_path}")
    proc = subprocess.run([exe, "-interaction=nonstopmode", "-halt-on-error", tex_path.name],
                          cwd=tex_path.parent, capture_output=True, text=True,
                          stdin=subprocess.DEVNULL)
    pdf = tex_path.with_suffix(".pdf")
    if proc.returncode != 0 or not pdf.exists():
        lines = proc.stdout.splitlines()
        first = next((i for i, line in enumerate(lines) if line.startswith("!")), None)
        detail = " ".join(lines[first:first + 2]) if first is not None else "no PDF produced"
        raise LmidslError(f"pdflatex failed on {tex_path}: {detail} (see {tex_path.with_suffix('.log')})")
    for suffix in (".aux", ".log"):
        tex_path.with_suffix(suffix).unlink(missing_ok=True)
    return pdf


def run(args):
    theorem = get_theorem(args.theorem)
    if args.example is not None:
        get_example(theorem, args.example)
    settings = {"star": r"\star" if args.star == "star" else "*", "he": args.he,
                "relation": args.relation}
    if args.lmi is not None:
        refuse(args, "--lmi prints one LMI's LaTeX as the theorem states it", "--example", "--data",
               "--set", "--backend", "--solver", "--solver-option", "--margin", "--pdf", "--output")
        text = lmi_snippet(theorem, args.lmi, **settings)
        if args.json:
            print_json({"theorem": theorem.id, "lmi": args.lmi, "latex": text})
        else:
            sys.stdout.write(text)
        return 0
    if args.output is not None:      # an unwritable -o is found before any solve
        if Path(args.output).suffix != ".tex":
            raise InputError(f"-o {args.output}: the output file must end in .tex")
        check_output_file(args.output, "-o")
    if args.pdf and shutil.which("pdflatex") is None and args.output is None:
        raise PdflatexMissing("--pdf: pdflatex is not installed (apt-get install texlive-latex-base)")
    solution = None
    if args.example is not None or args.data is not None or args.overrides:
        # solved: the document adds the numbers (γ, the design)
        solution = solve(theorem, **solve_arguments(args), **instance_spec(args))
    else:
        refuse(args, "the document of a theorem alone solves nothing; give --example, --data or --set",
               "--backend", "--solver", "--solver-option", "--margin")
    text = theorem_latex(theorem, solution, **settings)
    out = args.output
    if out is None and args.pdf:
        out = f"{theorem.id}.tex"
    document = {"theorem": theorem.id, "example": solution.example if solution else None,
                "solved": solution is not None, "latex": text}
    if solution is not None:       # the numbers in the document are the verdict's
        document.update(gamma=solution.gamma, verdict=solution.verdict.as_dict())
    if out is None:
        if args.json:
            print_json(document)
        else:
            sys.stdout.write(text)
        return 0
    path = Path(out)
    if path.suffix != ".tex":
        raise InputError(f"-o {out}: the output file must end in .tex")
    check_output_file(path, "-o")
    try:
        atomic_write_text(path, text)
    except OSError as exc:
        raise InputError(f"-o {out}: {exc.strerror}") from None
    written = [str(path)]
    if args.pdf:
        written.append(os.path.relpath(compile_pdf(path.resolve())))
    if args.json:
        print_json({**document, "written": written})
    else:
        for name in written:
            print(f"wrote {name}")
    return 0
