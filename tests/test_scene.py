"""Scene files: shipped scenes load, defaults come from one schema, bad input fails early with a
message that names the key, the value and what is expected (unknown keys with a did-you-mean)."""

from __future__ import annotations

import dataclasses
import textwrap
from pathlib import Path

import pytest

from rubberfriction.driver.fe.contact import DEFAULT_TANGENTIAL_FRACTION, METHODS
from rubberfriction.driver.fe.solid import ELEMENTS
from rubberfriction.driver.scenes import (
    SCHEMA,
    SceneError,
    load_scene,
    parse_scene,
    schema_text,
    shipped_scenes,
    surface_scale_names,
)
from rubberfriction.driver.multiscale.thermal_scene import macro_inputs
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.forms.material_files import load_compound, load_road


def scene_text(extra: str = "", surface: str = 'source = "sines"\namplitudes = [0.02, 0.002]\n'
               'wavelengths = [2.0, 0.2]\n') -> str:
    return textwrap.dedent(f"""
        name = "t"
        [surface]
        {surface}
        """) + textwrap.dedent(extra)


def parse(extra: str = "", **kw) -> object:
    return parse_scene(scene_text(extra, **kw), "t.toml", Path("."))


def error_of(text: str, base: Path | None = None) -> str:
    with pytest.raises(SceneError) as exc:
        parse_scene(text, "t.toml", base)
    return str(exc.value)


def test_shipped_scenes_load_and_are_consistent():
    assert {"default", "two_sine"} <= set(shipped_scenes())
    d = load_scene(None)
    assert d.name == "default" and d.variant == "rough"
    assert d.surface.source == "default_road"
    assert d.surface.stated_edges == (20.0, 3.0, 0.3, 0.04, 0.003)  # the thesis edges, cut by
    assert d.surface.edges == (20.0, 3.0, 0.3)  # the slope rule (tests/test_surfaces_cutoff.py)
    assert d.n_scales == 2 and d.conditions.pressures == (0.3,)
    assert len(d.conditions.velocities) >= 2
    assert d.conditions.T0 == pytest.approx(293.15)
    assert d.source == "embedded:default" and "[surface]" in d.text
    t = load_scene("two_sine")
    assert t.variant == "separated" and t.n_scales == 2
    assert t.surface.amplitudes == (0.075, 0.01) and t.surface.wavelengths == (5.0,
                                                                               0.5)  # eq. (6.8)
    assert t.conditions.pressures == (0.3,) and t.conditions.velocities == (500.0,)  # thesis 6.2.3
    assert t.separated is not None and t.separated.reference


def test_defaults_come_from_the_schema():
    s = parse()
    for section, keys in SCHEMA.items():
        if section in ("", "surface", "adhesion", "separated", "conditions", "thermal"):
            continue  # thermal: tests/test_thermal_scene.py (its config joins paired keys)
        obj = getattr(s, section)
        for name, key in keys.items():
            assert getattr(obj, name) == (tuple(key.default) if isinstance(key.default,
                                                                           list) else key.default)
    assert s.conditions.T0 is None  # WLF reference temperature
    assert s.output == Path("rf-results/t")
    text = schema_text()
    for section, keys in SCHEMA.items():
        for name in keys:
            assert f"\n{name} = " in "\n" + text, name


def test_unknown_key_and_section_get_a_did_you_mean():
    msg = error_of(scene_text("[numerics]\nelements_per_wavelenght = 8\n"))
    assert "[numerics].elements_per_wavelenght" in msg
    assert "did you mean 'elements_per_wavelength'" in msg
    msg = error_of(scene_text("[numeric]\ngrading = 1.2\n"))
    assert "unknown section numeric" in msg and "did you mean 'numerics'" in msg
    msg = error_of("nmae = 'x'\n")
    assert "did you mean 'name'" in msg


def test_type_and_range_errors_name_key_value_and_expectation():
    msg = error_of(scene_text('[conditions]\npressures = ["a"]\n'))
    assert "[conditions].pressures" in msg and "'a'" in msg and "expected a list of numbers" in msg
    msg = error_of(scene_text("[conditions]\nvelocities = [10.0, -1.0]\n"))
    assert "[conditions].velocities" in msg and "expected a list of numbers > 0" in msg
    msg = error_of(scene_text("[numerics]\ngrading = 0.9\n"))
    assert "[numerics].grading = 0.9" in msg and ">= 1" in msg
    msg = error_of(scene_text('[numerics]\ncontact = "morter"\n'))
    assert "'mortar'" in msg and "did you mean 'mortar'" in msg
    msg = error_of(scene_text("[samples]\nfriction = 2.5\n"))
    assert "[samples].friction = 2.5" in msg and "integer" in msg
    msg = error_of(scene_text('[conditions]\nT0 = -300\nT0_unit = "degC"\n'))
    assert "T0" in msg and "absolute zero" in msg


def test_missing_files_are_reported_with_their_key(tmp_path: Path):
    text = scene_text(surface='source = "files"\nfiles = ["nowhere.dat"]\nedges = [2.0, 0.2]\n')
    msg = error_of(text, tmp_path)
    assert "[surface].files[0] = 'nowhere.dat'" in msg and "file not found" in msg
    assert str(tmp_path) in msg
    msg = error_of(scene_text('[conditions]\ncompounds = ["tread_defualt"]\n'))
    assert "[conditions].compounds[0] = 'tread_defualt'" in msg
    assert "did you mean 'tread_default'" in msg
    msg = error_of(scene_text('[conditions]\ncompounds = ["my/compound.toml"]\n'), tmp_path)
    assert "[conditions].compounds[0]" in msg and "file not found" in msg


def test_inconsistent_scale_edges():
    msg = error_of(scene_text(surface="edges = [20.0, 3.0, 5.0]\n"))
    assert "[surface].edges = [20.0, 3.0, 5.0]" in msg and "descending" in msg
    msg = error_of(scene_text(surface="edges = [20.0]\n"))
    assert "at least two" in msg
    msg = error_of(scene_text(surface="edges = [20.0, 3.0, 0.3]\nblock_lengths = [20.0]\n"))
    assert "[surface].block_lengths" in msg and "2 entries, one per scale" in msg
    msg = error_of(scene_text(surface='source = "sines"\namplitudes = [0.02, 0.002]\nwavelengths = '
                              '[2.0, 0.2]\n'
                              "edges = [4.0, 1.0, 0.5]\n"))
    assert "wavelength 0.2 mm of scale 1 is outside its band 1-0.5 mm" in msg
    msg = error_of(scene_text(surface='source = "sines"\namplitudes = [0.02]\nwavelengths = [2.0, '
                                      '0.2]\n'))
    assert "[surface].amplitudes" in msg and "one amplitude per wavelength" in msg
    msg = error_of('name = "t"\nvariant = "separated"\n[surface]\nedges = [20.0, 3.0, 0.3, 0.04]\n')
    assert 'variant = "separated"' in msg and "exactly two scales" in msg and "gives 3" in msg


def test_edges_the_road_cannot_resolve_fail_at_a_stated_cutoff_and_drop_under_the_rule():
    text = 'name = "t"\n[surface]\nedges = [20.0, 3.0, 0.0005]\n'
    with pytest.raises(SceneError) as exc:
        parse_scene(text + "cutoff = 0.0005\n", "t.toml")
    msg = str(exc.value)
    assert "[surface]" in msg and "0.0005" in msg and "edges" in msg
    s = parse_scene(text, "t.toml")  # the slope rule: the band no measurement resolves is dropped
    assert s.surface.edges == (20.0, 3.0)
    assert "no measurement resolves it" in s.surface.cutoff_report.rows[1].reason


def test_physics_switches():
    msg = error_of(scene_text("[physics]\nthermal = true\n"))
    assert "[physics].thermal = true" in msg and "[thermal] table" in msg
    msg = error_of(scene_text("[physics]\nhysteresis = false\n"))
    assert "nothing" in msg
    msg = error_of(scene_text("[physics]\nadhesion = true\n"))
    assert "[adhesion] table" in msg
    s = parse("[physics]\nadhesion = true\n[adhesion]\ntau0 = 2.0\nc = 0.12\nv0 = 110.0\nalpha = "
              "0.5\n")
    assert s.adhesion is not None and s.adhesion.tau0 == 2.0 and s.adhesion.alpha == 0.5
    s = parse("[adhesion]\ntau0 = 2.0\n")
    assert s.adhesion is None and any("[adhesion] is ignored" in w for w in s.warnings)


def test_cli_reports_scene_errors_and_plans(tmp_path: Path, capsys):
    from rubberfriction.driver.cli.main import main

    bad = tmp_path / "bad.toml"
    bad.write_text(scene_text("[samples]\nfrction = 3\n"))
    assert main(["run", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "[samples].frction" in err and "did you mean 'friction'" in err
    assert main(["run", str(tmp_path / "missing.toml")]) == 2
    assert "no such file" in capsys.readouterr().err
    good = tmp_path / "good.toml"
    good.write_text(scene_text("[samples]\npressure = 2\nfriction = 3\n[conditions]\nvelocities = "
                               "[1.0, 10.0]\n"))
    assert main(["run", str(good), "--check"]) == 0
    out = capsys.readouterr().out
    # two scales: 1 scale x k=2 pressure runs + 2 scales x j=3 friction runs = 8 per point, 2 points
    assert "2 point(s) x 8 runs" in out and "= 16 single-scale runs" in out
    assert main(["run", "--schema"]) == 0
    assert "elements_per_wavelength" in capsys.readouterr().out


def _bad_compound(tmp_path: Path, C10: float, gamma: list[float]) -> Path:
    """A copy of the shipped m1 compound file with its C10 and an inline Prony series replaced."""
    from rubberfriction.forms.material_files import DATA_DIR

    text = (DATA_DIR / "m1.toml").read_text().replace("C10 = 0.174", f"C10 = {C10!r}")
    i, j = text.index("[prony]"), text.index("[wlf]")
    text = text[:i] + f"[prony]\ngamma = {gamma!r}\ntau = [0.01, 1.0]\n\n" + text[j:]
    path = tmp_path / "bad.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("C10,gamma,field", [(-0.1, [0.3, 0.2], "MooneyRivlin.C10"),
                                             (0.174, [0.7, 0.6], "gamma")])
def test_run_check_loads_every_compound_the_scene_names(tmp_path: Path, capsys, C10, gamma,
                                                        field) -> None:
    """``run --check`` reads the compound files (and surfaces) of the scene: a compound with
    C10 < 0 or sum(gamma) > 1 fails there, naming the field, before any campaign starts."""
    from rubberfriction.driver.cli.main import main

    _bad_compound(tmp_path, C10, gamma)
    scene = tmp_path / "scene.toml"
    scene.write_text('[surface]\nsource = "sines"\namplitudes = [0.01]\nwavelengths = [1.0]\n'
                     '[conditions]\ncompounds = ["bad.toml"]\n')
    assert main(["run", str(scene), "--check"]) == 2
    err = capsys.readouterr().err
    assert "[conditions].compounds[0] = 'bad.toml'" in err and field in err, err


def test_scene_choices_are_the_solvers_own():
    """The scene validates [numerics] element and contact against literal lists (the scene module
    stays free of dolfinx); they must be exactly what SolidSettings and Contact accept."""
    assert SCHEMA["numerics"]["element"].choices == ELEMENTS
    assert set(SCHEMA["numerics"]["contact"].choices) == set(METHODS.values())


def test_tangential_penalty_reaches_the_run_specs():
    """[numerics] tangential_penalty: the runs' c_T / c_N (macro spec of a thermal scene included);
    zero is refused."""
    s = parse("[numerics]\ntangential_penalty = 0.02\n")
    assert s.numerics.tangential_penalty == 0.02
    assert parse().numerics.tangential_penalty == 0.1
    assert SlidingSpec.tangential_penalty == DEFAULT_TANGENTIAL_FRACTION == 0.1  # one default
    t = dataclasses.replace(load_scene("thermal_macro"), numerics=s.numerics)
    spec, _ = macro_inputs(t, load_compound("m3"), load_road("r1"), 0.3, 10.0, 293.15, 0.9)
    assert spec.tangential_penalty == 0.02
    assert "tangential_penalty" in error_of(scene_text("[numerics]\ntangential_penalty = 0.0\n"))


def test_newton_rtol_reaches_the_runs_newton_solver():
    """[numerics] newton_rtol: the convergence test of every run's Newton solver (relative to the
    cell's load p L), per scale through [numerics.<scale>]; the default is the former fixed 1e-8;
    zero and values above 1e-3 are refused."""
    from rubberfriction.driver.multiscale.results import Point
    from rubberfriction.driver.multiscale.scales import build_scales
    from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds
    from rubberfriction.driver.sliding.run import SlidingRun, block_mesh, sliding_contact

    assert parse().numerics.newton_rtol == SlidingSpec.newton_rtol == 1e-8
    s = parse("[numerics]\nelements_per_wavelength = 6\nnewton_rtol = 1e-6\n"
              "[numerics.micro]\nnewton_rtol = 1e-7\n")
    assert s.numerics.newton_rtol == 1e-6
    scales = build_scales(s, 1)
    make = SpecBuilder(s, load_compounds(s))
    pt = Point(s.conditions.compounds[0], 0.3, 10.0)
    macro, micro = [make(pt, i, sc.samples[0], 0.3, None, "up") for i, sc in enumerate(scales.sets)]
    assert (macro.newton_rtol, micro.newton_rtol) == (1e-6, 1e-7)
    run = SlidingRun(micro, block_mesh, sliding_contact)
    run.build(micro.contact)
    assert run.model.newton.settings.rtol == 1e-7
    t = dataclasses.replace(load_scene("thermal_macro"), numerics=s.numerics)
    spec, _ = macro_inputs(t, load_compound("m3"), load_road("r1"), 0.3, 10.0, 293.15, 0.9)
    assert spec.newton_rtol == 1e-6  # the thermomechanical macro block's runs too
    for bad in ("0.0", "0.01"):
        assert "newton_rtol" in error_of(scene_text(f"[numerics]\nnewton_rtol = {bad}\n"))


def test_numerics_per_scale_reach_only_that_scales_runs():
    """[numerics.<scale>]: the runs on that scale take its values (element size from
    elements_per_wavelength, the element), the other scales the scene's; a scene without such
    tables builds the same specs as before (same store keys)."""
    from rubberfriction.driver.multiscale.results import Point
    from rubberfriction.driver.multiscale.scales import build_scales
    from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds
    from rubberfriction.driver.runtime.store import run_key

    base = parse("[numerics]\nelements_per_wavelength = 6\n")
    fine = parse("[numerics]\nelements_per_wavelength = 6\n"
                 "[numerics.micro]\nelements_per_wavelength = 12\nelement = \"Q1P0s\"\n")
    assert base.numerics.scales == ()
    assert fine.numerics.for_scale("micro").elements_per_wavelength == 12
    assert fine.numerics.for_scale("macro") == base.numerics
    scales = build_scales(base, 1)
    specs = {}
    for name, scene in (("base", base), ("fine", fine)):
        make = SpecBuilder(scene, load_compounds(scene))
        pt = Point(scene.conditions.compounds[0], 0.3, 10.0)
        specs[name] = [make(pt, i, s.samples[0], 0.3, None, "up")
                       for i, s in enumerate(scales.sets)]
    (b0, b1), (f0, f1) = specs["base"], specs["fine"]
    assert run_key(f0) == run_key(b0)  # the macro runs: untouched
    assert f1.h_contact == pytest.approx(0.5 * b1.h_contact)  # 0.2 mm / 12 against / 6
    assert (f1.element, b1.element) == ("Q1P0s", "Q1P0")
    assert run_key(f1) != run_key(b1)
    # the tables are found by the names the campaign labels its scales with, on roads too
    road = load_scene("captif_stress")
    names = [s.name for s in build_scales(road, 1).sets]
    assert names == surface_scale_names(road.surface) == ["macro", "meso", "micro1", "micro2"]


def test_numerics_per_scale_errors_name_the_table():
    """A per-scale table must name a scale of the scene, hold [numerics] keys (not the scene-wide
    window and wall clock) with valid values."""
    head = "[numerics]\nelements_per_wavelength = 6\n"
    err = error_of(scene_text(head + "[numerics.micr]\nelement = \"Q1P0s\"\n"))
    assert "[numerics.micr]" in err and "micro" in err and "macro, micro" in err
    err = error_of(scene_text(head + "[numerics.micro]\nwindow = \"fixed\"\n"))
    assert "[numerics.micro].window" in err and "scene-wide" in err
    err = error_of(scene_text(head + "[numerics.micro]\nelements_per_wavlength = 12\n"))
    assert "elements_per_wavlength" in err and "elements_per_wavelength" in err
    err = error_of(scene_text(head + "[numerics.micro]\nelements_per_wavelength = 1\n"))
    assert "elements_per_wavelength" in err and "1" in err
    assert "[numerics.<scale>]" in schema_text()


def test_trust_region_newton_reaches_the_runs_of_its_scale():
    """[numerics] newton (driver.fe.trust_region): per scale like every key; the trust region
    eliminates cell pressures, so Q1P0s with it is refused when the scene is read."""
    from rubberfriction.driver.multiscale.results import Point
    from rubberfriction.driver.multiscale.scales import build_scales
    from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds

    from rubberfriction.driver.sliding.run import NEWTON_METHODS

    assert parse().numerics.newton == "line-search" == SlidingSpec.newton
    assert SCHEMA["numerics"]["newton"].choices == NEWTON_METHODS
    scene = parse("[numerics.micro]\nnewton = \"trust-region\"\n")
    make = SpecBuilder(scene, load_compounds(scene))
    pt = Point(scene.conditions.compounds[0], 0.3, 10.0)
    specs = [make(pt, i, s.samples[0], 0.3, None, "up")
             for i, s in enumerate(build_scales(scene, 1).sets)]
    assert [sp.newton for sp in specs] == ["line-search", "trust-region"]
    err = error_of(scene_text("[numerics]\nnewton = \"trust-region\"\nelement = \"Q1P0s\"\n"))
    assert "trust-region" in err and "Q1P0s" in err and "[numerics]" in err
    err = error_of(scene_text("[numerics]\nelement = \"Q1P0s\"\n"
                              "[numerics.micro]\nnewton = \"trust-region\"\n"))
    assert "[numerics.micro]" in err and "Q1P0s" in err
    assert "newton" in error_of(scene_text("[numerics]\nnewton = \"trust\"\n"))


def test_run_check_lists_the_scales_with_their_numerics(tmp_path: Path, capsys):
    from rubberfriction.driver.cli.main import main

    f = tmp_path / "s.toml"
    f.write_text(scene_text("[numerics.micro]\nelements_per_wavelength = 12\n"))
    assert main(["run", str(f), "--check"]) == 0
    assert "scales: macro, micro (elements_per_wavelength = 12)" in capsys.readouterr().out


def test_pressure_branch_runs_wait_for_their_contact_fraction():
    """A pressure-branch run hands on the pooled pressure of eq. (6.11), p l / mean contact
    length, so its converged window waits for the contact fraction; friction-branch runs wait for
    mu (driver.sliding.window.WINDOW_QUANTITIES)."""
    from rubberfriction.driver.multiscale.results import Point
    from rubberfriction.driver.multiscale.scales import build_scales
    from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds
    from rubberfriction.driver.sliding.window import WINDOW_QUANTITIES

    scene = parse()
    make = SpecBuilder(scene, load_compounds(scene))
    pt = Point(scene.conditions.compounds[0], 0.3, 10.0)
    sample = build_scales(scene, 1).sets[0].samples[0]
    down, up = make(pt, 0, sample, 0.3, None, "down"), make(pt, 0, sample, 0.3, None, "up")
    assert (down.window_quantity, up.window_quantity) == ("contact", "mu")
    num = scene.numerics  # their own budget: frictionless runs, cheaper, slower to settle
    assert down.slide_distance == pytest.approx(num.pressure_slide_periods * down.period)
    assert up.slide_distance == pytest.approx(num.max_slide_periods * up.period)
    assert num.pressure_slide_periods == 24.0 and num.max_slide_periods == 12.0
    # with adhesion the friction branch's contact fractions make the real contact area (7.5)
    adhesive = parse("[physics]\nadhesion = true\n[adhesion]\ntau0 = 2.0\nc = 0.12\nv0 = 110.0\n")
    make = SpecBuilder(adhesive, load_compounds(adhesive))
    assert make(pt, 0, sample, 0.3, None, "up").window_quantity == "both"
    assert make(pt, 0, sample, 0.3, None, "down").window_quantity == "contact"
    assert set(WINDOW_QUANTITIES) == {"mu", "contact", "both"}
    assert SlidingSpec.window_quantity == "mu"
