"""Issue 38's smaller findings: XML that OpenMM's atoi/atof would read leniently (randomSeed="abc" as 0,
"12abc" as 12, friction="4.5xyz" as 4.5, stressAccumulation="7" as on) is refused naming the attribute
and its text, for every attribute of DPDForce and DPDIntegrator; and the errors of DPDForce.cast,
DPDIntegrator.cast and a DPDReporter that cannot open its file say what happened, once."""

import gc
import sys
import xml.etree.ElementTree as ElementTree

import openmm as mm
import pytest

import openmmdpd as dpd


def integrator_xml(forcing: bool) -> str:
    integrator = dpd.DPDIntegrator(temperature=1.0, friction=4.5, cutoff=1.0, step_size=0.01, scheme="ABOBA")
    integrator.setRandomNumberSeed(12)
    integrator.setParticleType(3, 1)
    integrator.addTypePair(0, 1, 2.0, 0.9)
    if forcing:
        integrator.setNorton(dpd.ShearProfile("sinusoidal"), 0.5)
    else:
        integrator.setStressAccumulation(True)
    return mm.XmlSerializer.serialize(integrator)


def force_xml() -> str:
    force = dpd.DPDForce(25.0, 1.0)
    force.setForceGroup(2)
    force.setParticleType(3, 1)
    force.addTypePair(0, 1, 12.0, 0.9)
    return mm.XmlSerializer.serialize(force)


def numeric_attributes(text: str):
    """(element path, attribute) for every attribute whose text is a number or a bool."""
    root = ElementTree.fromstring(text)
    found = []
    for path, element in [(".", root)] + [(f".//{e.tag}", e) for e in root.iter() if e is not root]:
        for name, value in element.attrib.items():
            try:
                float(value)
            except ValueError:
                continue
            found.append((path, name))
    return found


def replaced(text: str, path: str, attribute: str, value: str) -> str:
    root = ElementTree.fromstring(text)
    element = root if path == "." else root.find(path)
    element.set(attribute, value)
    return ElementTree.tostring(root, encoding="unicode")


CASES = [(name, xml, path, attribute) for name, xml in (("DPDIntegrator", integrator_xml(False)),
                                                       ("DPDIntegrator with Norton", integrator_xml(True)),
                                                       ("DPDForce", force_xml()))
         for path, attribute in numeric_attributes(xml)]


def test_every_numeric_attribute_is_covered():
    """The cases reach every number of both classes (so a new attribute read leniently would show)."""
    covered = {(name.split()[0], attribute) for name, _, _, attribute in CASES}
    expected = {("DPDIntegrator", a) for a in ("version", "temperature", "friction", "cutoff", "stepSize", "constraintTolerance",
                                                "integrationForceGroups", "randomSeed", "shearRate", "stressAccumulation",
                                                "index", "type", "type1", "type2", "strength")}
    expected |= {("DPDForce", a) for a in ("version", "forceGroup", "a", "cutoff", "index", "type", "type1", "type2")}
    assert expected <= covered, expected - covered


@pytest.mark.parametrize("name, xml, path, attribute", CASES, ids=[f"{c[0]}-{c[2]}-{c[3]}" for c in CASES])
@pytest.mark.parametrize("bad", ["abc", "12abc", "4.5xyz", "", " 1", "0x"])
def test_a_malformed_number_is_refused_naming_the_attribute_and_the_text(name, xml, path, attribute, bad):
    with pytest.raises(mm.OpenMMException, match=f"attribute {attribute}\\b.* is '{bad}', which is not"):
        mm.XmlSerializer.deserialize(replaced(xml, path, attribute, bad))


def test_a_bool_other_than_0_1_true_false_is_refused():
    xml = integrator_xml(False)
    with pytest.raises(mm.OpenMMException, match="attribute stressAccumulation is '7', which is not a bool"):
        mm.XmlSerializer.deserialize(replaced(xml, ".", "stressAccumulation", "7"))
    for text, expected in (("true", True), ("false", False), ("1", True), ("0", False)):
        loaded = dpd.DPDIntegrator.cast(mm.XmlSerializer.deserialize(replaced(xml, ".", "stressAccumulation", text)))
        assert loaded.getStressAccumulation() is expected


def test_well_formed_xml_still_round_trips():
    integrator = dpd.DPDIntegrator.cast(mm.XmlSerializer.deserialize(integrator_xml(True)))
    assert (integrator.getRandomNumberSeed(), integrator.getDefaultFriction(), integrator.getTypePairParameters(0)) == (12, 4.5, (0, 1, 2.0, 0.9))
    assert integrator.getForcing()[0] == "Norton"
    force = dpd.DPDForce.cast(mm.XmlSerializer.deserialize(force_xml()))
    assert (force.getForceGroup(), force.getDefaultA(), force.getParticleType(3)) == (2, 25.0, 1)


def test_an_unknown_forcing_mode_is_refused():
    xml = integrator_xml(True)
    with pytest.raises(mm.OpenMMException, match="attribute mode of <Forcing> is 'NEMDx', which is not NEMD or Norton"):
        mm.XmlSerializer.deserialize(replaced(xml, ".//Forcing", "mode", "NEMDx"))


@pytest.mark.parametrize("cast, argument, message", [
    (dpd.DPDForce.cast, mm.HarmonicBondForce(), "the Force is an openmm.HarmonicBondForce, not an openmmdpd.DPDForce"),
    (dpd.DPDForce.cast, None, "expected an openmm.Force, got None"),
    (dpd.DPDForce.cast, 3, "expected an openmm.Force, got a builtins.int"),
    (dpd.DPDIntegrator.cast, None, "expected an openmm.Integrator, got None"),
    (dpd.DPDIntegrator.cast, mm.VerletIntegrator(0.001), "the Integrator is an openmm.VerletIntegrator, not an openmmdpd.DPDIntegrator"),
    (dpd.DPDIntegrator.cast, mm.DPDIntegrator(300, 1, 1, 0.001), "the Integrator is an openmm.DPDIntegrator, not an openmmdpd.DPDIntegrator"),
    (dpd.DPDIntegrator.cast, dpd.DPDForce(), "expected an openmm.Integrator, got an openmmdpd.DPDForce"),
])
def test_cast_says_what_it_got(cast, argument, message):
    with pytest.raises(TypeError, match=message):
        cast(argument)


def test_cast_views_what_xml_gives_back():
    force = dpd.DPDForce.cast(mm.XmlSerializer.deserialize(force_xml()))
    assert dpd.DPDForce.cast(force).getDefaultA() == 25.0


def test_a_reporter_that_cannot_open_its_file_raises_once(tmp_path):
    unraisable = []
    previous, sys.unraisablehook = sys.unraisablehook, unraisable.append
    try:
        missing = tmp_path / "no such folder" / "report.csv"
        with pytest.raises(FileNotFoundError, match=f"DPDReporter: cannot open '{missing}' for writing"):
            dpd.DPDReporter(str(missing), 10, step=True)
        gc.collect()  # the half-made reporter's __del__ runs here: it must not raise (a second traceback)
    finally:
        sys.unraisablehook = previous
    assert unraisable == []
