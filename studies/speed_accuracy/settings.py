"""The settings of the speed-accuracy study (docs/studies/speed_accuracy.md): each changes one
knob of base.toml; the others keep the base's values. A setting is

    (name, knob, value label, {scene table: {key: TOML value}})

Every DEM setting is an ensemble of base.toml's 8 seeds. Its error is measured against its
knob's reference: for the numerical knobs (time step, integrator) the most accurate setting,
Verlet at the paper's 2e-6 s, pooled over its two realisations ("accurate" and "accurate_b";
tables.py); for the settling threshold the strictest; for the knobs
that change the model (corner count, tangential history, pour rate, grain count) the base, which
follows the paper.

The numerical knobs and their reference run with the Cundall-Strack spring as the tangential
history: the paper's literal eq. A.2 (`"total"`, the base's) stores the viscous term with the
spring, which makes the tangential stiffness grow as 1/dt (docs/DEM.md), so with it a change of
step is a change of the contact law, not a numerical error. `history_spring`, the spring at the
default step, is both the tangential-history knob's setting and the time-step knob's default.
"""

SPRING = {"dem.contact": {"tangential_history": '"spring"'}}


def spring(integrator):
    """The spring history with the given [dem.integrator] keys."""
    return {**SPRING, "dem.integrator": integrator}

DEM = [
    # name, knob, value, overrides; in the order run.py pours them: the cheapest first (the
    # paper's step and Gear 5 cost about 7 and 12 times the base).
    ("base", "reference", "leapfrog, 0.8 of the limit", {}),
    ("grains_400", "grain count", "400", {"dem": {"grain_count": "400"}}),
    ("rate_300", "pour rate", "300 grains/s", {"dem.pour": {"rate_grains_per_s": "300.0"}}),
    ("discs", "corners", "discs", {"dem.grains": {"shape": '"disc"'}}),
    ("settle_1e-6", "settling threshold", "1e-6 J", {"dem.settle": {"kinetic_energy_per_grain_J": "1e-6"}}),
    ("dt_f0.95", "time step", "0.95 of the limit", spring({"time_step_fraction": "0.95"})),
    ("history_spring", "tangential history", "spring (leapfrog, 0.8 of the limit)", SPRING),
    ("corners_12", "corners", "12", {"dem.grains": {"corners_min": "12", "corners_max": "12"}}),
    ("settle_1e-8", "settling threshold", "1e-8 J", {"dem.settle": {"kinetic_energy_per_grain_J": "1e-8"}}),
    ("corners_16", "corners", "16", {"dem.grains": {"corners_min": "16", "corners_max": "16"}}),
    ("corners_4", "corners", "4", {"dem.grains": {"corners_min": "4", "corners_max": "4"}}),
    ("dt_f0.5", "time step", "0.5 of the limit", spring({"time_step_fraction": "0.5"})),
    ("verlet", "integrator", "verlet, 0.8 of its limit", spring({"scheme": '"verlet"'})),
    ("rate_75", "pour rate", "75 grains/s", {"dem.pour": {"rate_grains_per_s": "75.0"}}),
    ("dt_8e-6", "time step", "8e-6 s", spring({"time_step_s": "8e-6"})),
    ("corners_3", "corners", "3", {"dem.grains": {"corners_min": "3", "corners_max": "3"}}),
    ("grains_1600", "grain count", "1600", {"dem": {"grain_count": "1600"}}),
    ("dt_4e-6", "time step", "4e-6 s", spring({"time_step_s": "4e-6"})),
    # The reference of the numerical knobs: Verlet (second order) at the paper's 2e-6 s.
    ("accurate", "reference", "verlet, 2e-6 s (the paper's step), spring history",
     spring({"scheme": '"verlet"', "time_step_s": "2e-6"})),
    ("gear5", "integrator", "gear5, 0.8 of its limit", spring({"scheme": '"gear5"'})),
    # The reference again, poured by a build that rounds the corners differently (f26adc4 on):
    # another realisation of the same seeds, whose difference from "accurate" is the noise of the
    # reference itself, which every numerical setting's difference shares.
    ("accurate_b", "reference realisation", "verlet, 2e-6 s, another realisation (a build from f26adc4 on)",
     spring({"scheme": '"verlet"', "time_step_s": "2e-6"})),
]

# The neighbour skin changes only the speed (the pairs tested exactly are the same for any
# skin): one pile each, whose grains must end where the default skin's (the first) do, exactly.
SKIN = [
    ("skin_0.3", "neighbour skin", "0.3 (default)", {}),
    ("skin_0.1", "neighbour skin", "0.1", {"dem.integrator": {"neighbour_skin_fraction": "0.1"}}),
    ("skin_1.0", "neighbour skin", "1.0", {"dem.integrator": {"neighbour_skin_fraction": "1.0"}}),
]

# Later stages on the base ensemble's members: no pouring.
LATER = [
    ("rve_30", "RVE size", "30 grains", {"coarse": {"rve_grain_count": "30"}}),
    ("rve_60", "RVE size", "60 grains (base)", {}),
    ("rve_120", "RVE size", "120 grains", {"coarse": {"rve_grain_count": "120"}}),
    ("rve_study", "RVE size", "the RVE study's choice", {"coarse": {"rve_grain_count": "0"}}),
    ("kernel_gaussian", "coarse-graining window", "gaussian kernel", {"coarse": {"method": '"gaussian"'}}),
    ("kernel_lucy", "coarse-graining window", "Lucy kernel", {"coarse": {"method": '"lucy"'}}),
    ("mesh_0.012", "mesh size", "0.012 m", {"mesh": {"element_size_m": "0.012"}}),
    ("mesh_0.003", "mesh size", "0.003 m", {"mesh": {"element_size_m": "0.003"}}),
    ("degree_1", "element degree", "P1", {"continuum.elastic": {"degree": "1"}, "continuum.fpa": {"degree": "1"}}),
]

# Settings that also stand for a point of another knob: (name, knob, value).
ALSO = [("history_spring", "time step", "0.8 of the limit (the default), spring history")]

# Which setting each knob's errors are measured against.
# The numerical knobs' reference is the mean of "accurate" and "accurate_b" (tables.py pools
# them): one realisation of 8 piles was off by 2.8 degrees of stress tilt from the other.
REFERENCE = {
    "time step": "accurate_pooled", "integrator": "accurate_pooled", "settling threshold": "settle_1e-8",
    "corners": "base", "tangential history": "base", "pour rate": "base", "grain count": "base",
    "reference": None,  # each is its own
    "reference realisation": "accurate",
    "RVE size": "rve_study", "coarse-graining window": "rve_60", "mesh size": "mesh_0.003",
    "element degree": "rve_60",
}
