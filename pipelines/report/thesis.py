"""The thesis' sentences that the report quotes beside our numbers, as data: a key per sentence,
its text as the thesis prints it (symbols in Unicode) and its line numbers in the thesis' source.
render.quote(key) sets one as a Markdown block quote; the chapter modules name them by key."""

SENTENCES = {
    # Chapter 4, simple shear (§4.2.2)
    "bagnold_pressure": (
        "Although the shear rates in the plots differ by a factor of 10^4, the normalized pressure is "
        "virtually identical for both systems.",
        "362–369",
    ),
    "bagnold_invariance": (
        "The invariance in Newton's equations also predicts that sγ̇⁻² and Tγ̇⁻² are independent of γ̇. "
        "For all of the simulations we have carried out these predictions from the invariance are upheld",
        "371",
    ),
    "steady_reached": ("For all quantities, steady flow is reached by a shear of approximately 0.5", "377"),
    "fluctuations": ("the values of s/p and mT/p⟨R⟩² fluctuate much more than γ̇⟨R⟩/√T", "377"),
    "dense_increase": (
        "for packing fractions larger than 0.75 there is a large increase in the values of the stresses "
        "and granular temperature",
        "384",
    ),
    "stress_diverges": ("Both the shear stress and pressure are seen to diverge at a finite packing fraction", "386"),
    "n1_previous": ("Previous research [71, 27] has shown that N_1 ∼ 10^-2.", "358"),
    "static_over_kinetic": ("We see that the static part of the pressure becomes larger than the kinetic part for ν > 0.4.", "404"),
    "pressure_independent_of_e": ("For large packing fractions the pressures become independent of e.", "408"),
    "variance_with_e": (
        "At low values of packing fraction the dynamics becomes less linked to geometric constraints and "
        "there is a large variance with e.",
        "408",
    ),
    # Chapter 4, incline flow (§4.3–4.4)
    "incline_bulk_profiles": (
        "In the bulk of the flow, where the boundaries do not play a role, the packing fraction is "
        "constant and the granular temperature is linear. The y-dependence of the average flow velocity "
        "is very close to y^{3/2}",
        "449",
    ),
    "incline_invariants": ("These three invariant quantities should only depend on the packing fraction and *not* on y.", "461"),
    "shear_incline_match": (
        "Data from simple shear flow (circles) and flow down an incline (squares) match on the same "
        "curves for both cases.",
        "489",
    ),
    "critical_angle": (
        "We identify the critical angle θ_c by the angle below which the average velocity fluctuates "
        "around zero.",
        "434",
    ),
    # Chapter 5, microstructure (§5.1–5.3)
    "xi_dilute_limit": (
        "For small values of packing fraction, Figure 5.3 shows the value of ξ approaching a limiting "
        "value of 0.785σ.",
        "555",
    ),
    "xi_grows": (
        "We notice that ξ is an increasing function of density for each value of restitution. We also "
        "notice, in agreement with Figure 5.1, that ξ increases as e decreases.",
        "553",
    ),
    "pf_peak": (
        "For ξ/ξ_el ≤ 1.25 there is a clear peak, whereas for ξ/ξ_el ≥ 1.25, the peak disappears and the "
        "maximum occurs at f = 0.",
        "645",
    ),
    "nu_bc_friction": (
        "This plot is for frictionless materials μ = 0, but increasing the value of μ does not change "
        "the curve.",
        "668",
    ),
    "anisotropy_fit": (
        "The solid curve in Figure 5.6 is a fit to this equation, which sets the parameters as a_0 = "
        "0.21 and θ_0 = 0.013.",
        "605",
    ),
    "clusters": (
        "For e = 0.92 the interacting grains are well spaced and tend to occur in pairs, whereas for e = "
        "0 the interacting grains tend to form large clusters.",
        "510",
    ),
    # Chapter 5, ν_c
    "nu_c_diverges": (
        "The data in Figures 5.3 and 5.4 demonstrates that ξ diverges at a finite packing fraction ν_c "
        "that depends on the friction coefficient μ, but not on the restitution coefficient e.",
        "568",
    ),
    # Chapter 6, kinetic theory (§6.1)
    "binary_regime": (
        "For now, it is only important to notice that there is a regime where the binary collision "
        "assumption holds and the normalized stress tensors are equal. The bounds of this regime depend "
        "on the value of both the restitution coefficient and the packing fraction.",
        "739",
    ),
    "pressure_prediction": (
        "We immediately notice that the prediction for the pressure matches the measured pressure in all "
        "of the dilute systems we have investigated.",
        "798",
    ),
    "shear_prediction": (
        "The prediction for the shear stress also matches the data in the dilute regime quite well for "
        "large restitution.",
        "800",
    ),
    "velocity_correlation": (
        "This definition yields a positive value when pre-collisional grain velocities tend to be "
        "aligned, and for all restitution coefficients we observe that the correlations are positive. In "
        "addition, the magnitude of the discrepancy between measured and predicted shear stress is "
        "roughly proportional to the size of the velocity correlations.",
        "806",
    ),
    # Chapter 6, the force-network model (§6.2)
    "phi_constant": (
        "Although z and Ψ depend sensitively on the value of ν and e , the value of Φ is always "
        "approximately 0.83.",
        "953",
    ),
    "psi_below_phi": ("We observe that $\\Psi < \\Phi$ for all granular materials we have considered.", "955"),
    "next_order": (
        "The size of the components is always of order 10^{-1} whereas the magnitude of the next order "
        "coefficients in the Fourier Series is less than 10^{-2} .",
        "910",
    ),
    "z_time_step": ("This measurement of z does not depend on the time step, as is shown in the inset.", "955"),
    "collapse": (
        "Plotted in this way, the data for each component of the stress tensor collapses onto the line "
        "predicted by the force-network model over at least four decades.",
        "957",
    ),
    # Chapter 6, D²min (§6.3, Fig. 6.9)
    "d2min_clusters": (
        "We notice that there is a tendency for the regions of non-affine displacement to form clusters, "
        "and the size of the resulting non-affine regions is about the same in both (a) and (b).",
        "1008",
    ),
    "d2min_locations": (
        "comparing (a) and (d), we notice that the size of the non-affine regions is about the same in "
        "the two figures, but the locations are different.",
        "1015",
    ),
    # Chapter 6, the STZ law (§6.3)
    "stz_fits": ("The line is the STZ prediction, which fits the data very well.", "1055"),
    "stz_incline": ("find that the incline flow data is predicted using the exact same coefficients!", "1077"),
    "repose_angle": (
        "θ^* is identified as the repose angle of the granular material, whose value is predicted by STZ "
        "theory.",
        "1045",
    ),
}
