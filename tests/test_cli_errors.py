"""Every user error of the ``rubberfriction`` command is one line on stderr, never a traceback.

A table of bad inputs -- scene values, compound files, profile files, missing files, impossible
options of ``surface``, ``verify``, ``theory``, ``samples-study`` and ``material`` -- goes through
the command's entry point (``rubberfriction.driver.cli.main.main``, in process).  For each: the
exit status is 2 (the command line's input-error status), stderr is exactly one line with no
"Traceback", the message names the option or field as the user typed it, and nothing was
written (the ``run`` cases' output folder does not exist afterwards).  Nothing here computes: every
case stops at the input check (the ``verify`` cases before any mesh is built).
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from rubberfriction import validation as V
from rubberfriction.driver.cli import main as cli_main
from rubberfriction.driver.cli.surface import option_message
from rubberfriction.forms.material_files import resolve_data_path

SINES_SCENE = """name = "bad"
output = "{out}"
[surface]
source = "sines"
amplitudes = [0.075, 0.01]
wavelengths = [5.0, 0.5]
[conditions]
compounds = [{compound}]
pressures = [{p}]
velocities = [{v}]
"""


def _scene(tmp: Path, name: str, *, p: str = "0.3", v: str = "10.0",
           compound: str = '"tread_default"') -> str:
    path = tmp / name
    path.write_text(SINES_SCENE.format(out=tmp / "out", p=p, v=v, compound=compound))
    return str(path)


def _files(tmp: Path) -> None:
    """The malformed profile files (and a bad compound) a new user might try."""
    x = 0.01 * np.arange(200)
    (tmp / "empty.csv").write_text("")
    (tmp / "header.csv").write_text("x,h\n")
    (tmp / "onecol.csv").write_text("\n".join(f"{v:.4f}" for v in np.sin(x[:40])) + "\n")
    (tmp / "dup.csv").write_text("x,h\n" + "".join(f"{0 if i < 2 else i},{i}\n" for i in range(30)))
    rows = "".join(f"{i},{i}\n" for i in range(3, 30))
    (tmp / "nonmono.csv").write_text("x,h\n0,1\n2,2\n1,3\n" + rows)
    (tmp / "nan.csv").write_text("x,h\n" + "".join(f"{i},nan\n" for i in range(30)))
    (tmp / "text.txt").write_text("hello world\nthis is text\nnot numbers\n")
    (tmp / "short.csv").write_text("x,h\n0,1\n1,2\n2,1\n")
    rows = "".join(f"{a:.4f},{np.sin(a):.5f},{np.cos(a):.5f}\n" for a in x)
    (tmp / "three.csv").write_text("x,a,b\n" + rows)
    rows = "".join(f"{a:.4f},{0.01 * np.sin(20 * a):.6f}\n" for a in x)
    (tmp / "good.csv").write_text("x,h\n" + rows)
    # a position column that is not one (the last row 1e12 mm away): numpy's "array is too big"
    far = np.r_[0.1 * np.arange(40), 1e12]
    (tmp / "farx.csv").write_text("x,h\n" + "".join(f"{a:.6g},{np.sin(a):.4f}\n" for a in far))
    # positions 1700 km from the origin in 1 um steps: double precision cannot keep them uniform
    rows = "".join(f"{1.7e9 + 1e-3 * i:.4f},{np.sin(i):.4f}\n" for i in range(200))
    (tmp / "offset.csv").write_text("x,h\n" + rows)
    text = resolve_data_path("tread_default").read_text()
    assert "\nC10 = 0.174" in text  # the line the bad compound changes
    (tmp / "badc.toml").write_text(text.replace("\nC10 = 0.174", "\nC10 = -0.1"))
    # DMA inputs of ``material fit``: a master curve, shift-factor tables, Prony terms
    f = np.logspace(-1, 4, 11)
    rows = "".join(f"{a:.6g},{1 + 0.1 * np.log10(a):.6g},{0.2:.6g}\n" for a in f)
    (tmp / "dma.csv").write_text("f,E_stor,E_loss\nHz,MPa,MPa\n" + rows)
    (tmp / "relax.csv").write_text("t,E_relax\ns,MPa\n" + "".join(
        f"{a:.6g},{2 + 1 / (1 + a):.6g}\n" for a in f))
    (tmp / "shift.csv").write_text("T,log_aT\nC, -\n-20,2.5\n-5,0\n20,-3\n40,-5\n")
    (tmp / "shift_nounits.csv").write_text("T,log_aT\n-20,2.5\n-5,0\n20,-3\n40,-5\n")
    (tmp / "prony_neg.csv").write_text("# E0 = 100 MPa\n0.2,1\n-0.1,10\n")


# (id, argv (strings; {tmp} is the test folder), what the message must contain, as typed)
CASES: list[tuple[str, list[str], list[str]]] = [
    # surface analyse: missing and malformed profile files
    ("missing-file", ["surface", "analyse", "{tmp}/missing.csv"], ["missing.csv", "not found"]),
    ("empty", ["surface", "analyse", "{tmp}/empty.csv"], ["empty.csv", "empty file"]),
    ("header-only", ["surface", "analyse", "{tmp}/header.csv"], ["header.csv"]),
    ("one-column", ["surface", "analyse", "{tmp}/onecol.csv"], ["onecol.csv", "--dx"]),
    ("duplicate-x", ["surface", "analyse", "{tmp}/dup.csv"], ["dup.csv", "not monotonic"]),
    ("non-monotonic", ["surface", "analyse", "{tmp}/nonmono.csv"],
     ["nonmono.csv", "not monotonic"]),
    ("all-nan", ["surface", "analyse", "{tmp}/nan.csv"], ["nan.csv", "dropouts"]),
    ("text", ["surface", "analyse", "{tmp}/text.txt"], ["text.txt", "no rows of numbers"]),
    ("too-short", ["surface", "analyse", "{tmp}/short.csv"], ["short.csv", "valid heights"]),
    ("three-columns", ["surface", "analyse", "{tmp}/three.csv"],
     ["three.csv", "--x-col", "--h-col"]),
    ("x-col-out-of-range", ["surface", "analyse", "{tmp}/three.csv", "--x-col", "7"],
     ["--x-col 7", "0 to 2"]),
    ("x-col-unknown-name", ["surface", "analyse", "{tmp}/three.csv", "--x-col", "foo"],
     ["--x-col 'foo'"]),
    ("far-positions", ["surface", "analyse", "{tmp}/farx.csv"], ["farx.csv", "--x-col"]),
    ("offset-positions", ["surface", "analyse", "{tmp}/offset.csv"],
     ["offset.csv", "too large for the spacing"]),
    ("units", ["surface", "analyse", "{tmp}/good.csv", "--units", "parsec"],
     ["--units parsec", "mm"]),
    ("dx-zero", ["surface", "analyse", "{tmp}/onecol.csv", "--dx", "0"], ["--dx 0", "> 0"]),
    ("psd-fit-order", ["surface", "analyse", "{tmp}/good.csv", "--psd-fit", "0.1", "1"],
     ["--psd-fit 0.1 1"]),
    ("hdc-range-order", ["surface", "analyse", "{tmp}/good.csv", "--hdc-range", "1", "0.1"],
     ["--hdc-range 1 0.1"]),
    ("edges-ascending", ["surface", "split", "{tmp}/good.csv", "--edges", "1", "3", "--out",
                         "{tmp}/split"], ["--edges 1 3", "descending"]),
    ("generate-dx", ["surface", "generate", "two-sine", "--dx", "-1", "--out", "{tmp}/g.csv"],
     ["--dx -1"]),
    ("road-cutoff", ["surface", "four-scale", "--cutoff", "foo", "--out", "{tmp}/road"],
     ["--cutoff 'foo'"]),
    # verify: impossible parameters, refused before a mesh is built
    ("hertz-R", ["verify", "hertz", "--R", "-1"], ["--R -1: expected a radius > 0"]),
    ("hertz-nu", ["verify", "hertz", "--nu", "0.5"], ["--nu 0.5", "Poisson"]),
    ("hertz-E-nan", ["verify", "hertz", "--E", "nan"], ["--E nan", "finite"]),
    ("hertz-elements", ["verify", "hertz", "--elements-per-a", "4", "0"],
     ["--elements-per-a 4 0"]),
    ("sliding-mu", ["verify", "sliding-block", "--mu", "-0.1"], ["--mu -0.1"]),
    ("sliding-edge", ["verify", "sliding-block", "--edge-radius", "-1", "--frame", "master"],
     ["--edge-radius -1"]),
    ("thermal-kappa", ["verify", "thermal-bars", "--kappa", "2"], ["--kappa 2"]),
    ("relaxation-tau", ["verify", "relaxation", "--tau", "0.1", "-1"], ["--tau 0.1 -1"]),
    ("sliding-frame", ["verify", "sliding-block", "--frame", "foo"], ["--frame foo", "master"]),
    ("hertz-method", ["verify", "hertz", "--method", "mortr"], ["--method mortr", "'mortar'"]),
    ("verify-compound", ["verify", "sawtooth", "--compound", "{tmp}/badc.toml"],
     ["--compound", "C10 = -0.1"]),
    # run: scene values, compound files, surface files, missing files, command-line options
    ("pressure-huge", ["run", "{scene:p=1e9}", "--check"], ["[conditions].pressures", "1000"]),
    ("velocity-huge", ["run", "{scene:v=1e6}"], ["[conditions].velocities", "100000"]),
    ("pressure-zero", ["run", "{scene:p=0.0}"], ["[conditions].pressures", "> 0"]),
    ("unknown-key", ["run", "{scene:extra=pressure}"], ["[conditions].pressure", "did you mean"]),
    ("compound-field", ["run", "{scene:compound=badc.toml}"], ["C10 = -0.1", "badc.toml"]),
    ("compound-missing", ["run", "{scene:compound=nosuch.toml}", "--check"],
     ["[conditions].compounds[0]", "nosuch.toml"]),
    ("surface-file-missing", ["run", "{scene:files=missing.csv}"],
     ["[surface].files[0]", "missing.csv"]),
    ("surface-file-empty", ["run", "{scene:files=empty.csv}"], ["empty.csv", "empty file"]),
    ("scene-missing", ["run", "{tmp}/nosuch_scene.toml"], ["nosuch_scene.toml"]),
    ("samples", ["run", "{scene:}", "--samples", "0", "1"], ["--samples 0 1"]),
    ("show", ["run", "--show", "nosuch"], ["--show 'nosuch'"]),
    ("study-n", ["samples-study", "{scene:}", "--n", "1"], ["--n 1"]),
    ("study-pressure", ["samples-study", "{scene:}", "--pressure", "2000"], ["--pressure 2000"]),
    ("trends-flash-cutoff", ["study", "trends", "--check", "--flash-cutoff", "0.001", "--out",
                             "{tmp}/t"], ["--flash-cutoff 0.001", ">= 0.003 and <= 3 in mm"]),
    # theory, adhesion and material
    ("adhesion-pressure", ["adhesion", "fit", "--dry", "{tmp}/good.csv", "--area",
                           "{tmp}/good.csv", "--pressure", "-1", "--json", "{tmp}/fit.json"],
     ["--pressure -1"]),
    ("theory-pressure", ["theory", "--pressure", "-1"], ["--pressure -1"]),
    ("theory-velocities", ["theory", "--velocities", "0"], ["--velocities 0"]),
    ("material-missing", ["material", "show", "nosuch"], ["nosuch", "not found"]),
    ("material-fit-missing", ["material", "fit", "{tmp}/missing.csv", "--T-ref-C", "20"],
     ["missing.csv"]),
    ("material-fit-no-T-ref", ["material", "fit", "{tmp}/dma.csv"],
     ["--T-ref-C", "--shift-factors", "nothing is assumed"]),
    ("material-fit-T-ref", ["material", "fit", "{tmp}/dma.csv", "--T-ref-C", "-300"],
     ["--T-ref-C -300", "> -273.15"]),
    ("material-fit-shift-missing", ["material", "fit", "{tmp}/dma.csv", "--shift-factors",
                                    "{tmp}/nosuch.csv"], ["--shift-factors", "nosuch.csv"]),
    ("material-fit-shift-units", ["material", "fit", "{tmp}/dma.csv", "--shift-factors",
                                  "{tmp}/shift_nounits.csv"],
     ["--shift-factors", "shift_nounits.csv", "temperature unit"]),
    ("material-fit-shift-vs-T-ref", ["material", "fit", "{tmp}/dma.csv", "--shift-factors",
                                     "{tmp}/shift.csv", "--T-ref-C", "20"],
     ["--T-ref-C 20", "--shift-factors", "-5 degC"]),
    ("material-fit-terms-time", ["material", "fit", "{tmp}/relax.csv", "--kind", "time",
                                 "--T-ref-C", "20", "--terms", "5"], ["--terms", "--kind time"]),
    ("material-fit-columns", ["material", "fit", "{tmp}/relax.csv", "--kind", "time",
                              "--T-ref-C", "20", "--columns", "t"], ["--columns t", "2 column"]),
    ("material-fit-prony-negative", ["material", "fit", "{tmp}/prony_neg.csv", "--kind", "prony",
                                     "--T-ref-C", "20"], ["prony_neg.csv", "negative modulus"]),
]


def _argv(argv: list[str], tmp: Path) -> list[str]:
    """Fill in {tmp} and {scene:KEY=VALUE} (a sines scene with one thing changed: p, v,
    compound, a misspelt [conditions] key, or surface files)."""
    out = []
    for a in argv:
        if not a.startswith("{scene:"):
            out.append(a.replace("{tmp}", str(tmp)))
            continue
        key, _, val = a[len("{scene:"):-1].partition("=")
        kw = {"p": {"p": val}, "v": {"v": val}, "compound": {"compound": f'"{val}"'}}.get(key, {})
        path = Path(_scene(tmp, "scene.toml", **kw))
        text = path.read_text()
        if key == "extra":  # [conditions] pressure (for pressures)
            text = text.replace("pressures = [0.3]", "pressure = [0.3]")
        elif key == "files":
            text = text.replace('source = "sines"\namplitudes = [0.075, 0.01]\n'
                                'wavelengths = [5.0, 0.5]',
                                f'source = "files"\nfiles = ["{val}"]\nedges = [20.0, 3.0, 0.3]')
        path.write_text(text)
        out.append(str(path))
    return out


@pytest.mark.parametrize("argv,expected", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_input_is_one_line(argv: list[str], expected: list[str], tmp_path: Path,
                               capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch
                               ) -> None:
    _files(tmp_path)
    monkeypatch.chdir(tmp_path)
    before = sorted(p.name for p in tmp_path.iterdir())
    code = cli_main.main(_argv(argv, tmp_path))
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert code == 2, err
    assert len(lines) == 1 and "Traceback" not in err, err
    assert "error:" in lines[0]
    for text in expected:
        assert text in lines[0], (text, lines[0])
    assert not (tmp_path / "out").exists()  # the run cases' output folder (and store)
    after = sorted(p.name for p in tmp_path.iterdir())
    assert set(after) - set(before) <= {"scene.toml"}, after  # nothing else was written


@pytest.mark.parametrize("argv,expected", [
    (["verify", "hertz", "--R", "abc"], "argument --R: invalid float value: 'abc'"),
    (["surface", "split", "good.csv"], "required: --edges, --out"),
    (["run", "--samples", "1"], "argument --samples: expected 2 arguments"),
    (["surface", "analyse", "good.csv", "--window", "foo"], "argument --window"),
    (["verify", "nosuch"], "invalid choice: 'nosuch'"),
])
def test_command_line_syntax_is_one_line(argv: list[str], expected: str,
                                         capsys: pytest.CaptureFixture) -> None:
    """argparse's own errors (bad type, missing or unknown option) are one line too, status 2."""
    with pytest.raises(SystemExit) as exc:
        cli_main.main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert exc.value.code == 2
    assert len(err) == 1 and expected in err[0] and "--help" in err[0], err


def test_table_size() -> None:
    """The brief asks for at least 30 bad inputs."""
    assert len(CASES) >= 30


def test_failed_points_end_in_one_line(tmp_path: Path, capsys: pytest.CaptureFixture,
                                       monkeypatch: pytest.MonkeyPatch) -> None:
    """A run that did not converge is a recorded failure (exit status 1), summed up in one line
    on stderr at the end, not a traceback (the campaign itself is replaced: nothing computes)."""
    from rubberfriction.driver.multiscale import campaign

    def point(ok: bool, reason: str = "") -> SimpleNamespace:
        return SimpleNamespace(ok=ok, reason=reason,
                               point=SimpleNamespace(id="tread_default/p=0.3/v=10"))

    reason = "newton: no convergence after 6 cut-backs at step 14\nTraceback (most recent ..."
    fake = SimpleNamespace(points=[point(True), point(False, reason)], output=tmp_path / "out")
    monkeypatch.setattr(campaign, "run_scene", lambda scene, **kw: fake)
    code = cli_main.main(["run", _scene(tmp_path, "scene.toml"), "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1
    assert err == [f"rubberfriction: 1 of 2 point(s) failed (first: tread_default/p=0.3/v=10: "
                   f"newton: no convergence after 6 cut-backs at step 14); see "
                   f"{tmp_path / 'out' / 'results.csv'}"]


def test_real_bugs_keep_their_traceback(monkeypatch: pytest.MonkeyPatch) -> None:
    """The safety net catches InputError only: any other exception (a bug) propagates."""
    from rubberfriction.driver.verification import hertz

    def bug(args):
        raise ZeroDivisionError("a bug")

    monkeypatch.setattr(hertz, "run", bug)
    with pytest.raises(ZeroDivisionError):
        cli_main.main(["verify", "hertz"])


def test_option_message_and_option_check() -> None:
    """Library keyword hints read as options; V.option names the option as typed."""
    assert option_message("pass x_col= and h_col=") == "pass --x-col and --h-col"
    assert option_message("units='mm' was declared; use units='auto'") == \
        "--units mm was declared; use --units auto"
    assert option_message("x_col = 7: expected") == "--x-col 7: expected"
    assert option_message("the dx of the grid") == "the dx of the grid"
    with pytest.raises(V.InputError, match=r"^--R -1: expected a radius > 0 in mm$"):
        V.option("--R", -1.0, what="a radius", above=0.0, unit="mm")
    assert V.option("--R", 2.0, what="a radius", above=0.0) == 2.0
    assert V.option("--R", None, what="a radius", above=0.0) is None


def test_verify_defaults_pass_the_checks() -> None:
    """The parameter checks reject nothing a case runs with by default (every case, every
    option at its default, material files included)."""
    from rubberfriction.driver.verification.parameters import check_parameters

    parser = cli_main.build_parser()
    verify = parser._subparsers._group_actions[0].choices["verify"]
    cases = verify._subparsers._group_actions[0].choices
    assert "hertz" in cases and "sliding-block" in cases
    for name, case_parser in cases.items():
        check_parameters(case_parser, parser.parse_args(["verify", name]))
