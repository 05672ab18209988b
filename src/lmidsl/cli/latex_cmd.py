"""``lmidsl latex``: the theorem as a LaTeX document (and a PDF with ``--pdf``)."""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from ..errors import InputError, LmidslError
from ..studies.store import atomic_path, atomic_write_text, check_output_file
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


#: kpathsea's paranoid file access for the pdflatex run: no file opened for reading or writing
#: outside the working folder (no absolute path, no ``..``, no dot file), no shell escape
PDFLATEX_ENV = {"openin_any": "p", "openout_any": "p", "shell_escape": "f"}
#: the job name of every run: the user's file name never reaches TeX's command line
JOB = "lmidsl-document"


def compile_pdf(tex_path: Path) -> Path:
    """Run pdflatex on a copy of ``tex_path`` in a fresh temporary folder (job :data:`JOB`,
    :data:`PDFLATEX_ENV`, ``-no-shell-escape``) and move only the PDF beside ``tex_path``: no
    file of that folder (a log, an aux file of the user's) is read, written or deleted.  The PDF
    path, or a one-line error (pdflatex's log then kept beside the source under a free name)."""
    exe = shutil.which("pdflatex")
    if exe is None:
        raise PdflatexMissing(
            f"--pdf: pdflatex is not installed (apt-get install texlive-latex-base); "
            f"the LaTeX source is in {tex_path}")
    env = {k: v for k, v in os.environ.items() if k != "TEXMFOUTPUT"}   # no absolute path allowed
    env.update(PDFLATEX_ENV)
    with tempfile.TemporaryDirectory(prefix="lmidsl-latex-") as folder:
        work = Path(folder)
        shutil.copyfile(tex_path, work / f"{JOB}.tex")
        proc = subprocess.run([exe, "-no-shell-escape", "-interaction=nonstopmode", "-halt-on-error",
                               f"{JOB}.tex"], cwd=work, env=env, capture_output=True, text=True,
                              errors="replace", stdin=subprocess.DEVNULL)
        built = work / f"{JOB}.pdf"
        if proc.returncode != 0 or not built.exists():
            lines = proc.stdout.splitlines()
            first = next((i for i, line in enumerate(lines) if line.startswith("!")), None)
            detail = " ".join(lines[first:first + 2]) if first is not None else "no PDF produced"
            log = _free_name(tex_path.with_suffix(".log"))
            if (work / f"{JOB}.log").exists():
                shutil.copyfile(work / f"{JOB}.log", log)
            raise LmidslError(f"pdflatex failed on {tex_path}: {detail} (see {log})")
        pdf = tex_path.with_suffix(".pdf")
        with atomic_path(pdf) as tmp:
            shutil.copyfile(built, tmp)
    return pdf


def _free_name(path: Path) -> Path:
    """``path``, or ``stem-1.log``, ``stem-2.log``, ... : a name no file has (never overwrite)."""
    k, candidate = 0, path
    while candidate.exists():
        k += 1
        candidate = path.with_name(f"{path.stem}-{k}{path.suffix}")
    return candidate


def default_tex_name(theorem_id: str) -> Path:
    """``THEOREM.tex`` in the working folder for ``--pdf`` without ``-o``: the id's characters
    other than letters, digits, ``.``, ``_``, ``+`` and ``-`` replaced by ``_`` (an id
    ``../../x`` or ``a/b`` stays in the working folder)."""
    name = re.sub(r"[^A-Za-z0-9._+-]", "_", theorem_id).lstrip(".") or "theorem"
    return Path(f"{name}.tex")


def run(args):
    theorem = get_theorem(args.theorem)
    # sympy's printer, once the theorem id is known good; the solving stack only to solve
    from ..render.latex_document import lmi_snippet, theorem_latex
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
        from ..pipeline import solve
        solution = solve(theorem, **solve_arguments(args), **instance_spec(args))
    else:
        refuse(args, "the document of a theorem alone solves nothing; give --example, --data or --set",
               "--backend", "--solver", "--solver-option", "--margin")
    text = theorem_latex(theorem, solution, **settings)
    out = args.output
    if out is None and args.pdf:
        out = str(default_tex_name(theorem.id))
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
