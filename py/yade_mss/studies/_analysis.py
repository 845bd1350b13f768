"""What a triaxial test's records say: the derived figures of soil mechanics, from the recorded curve alone
(numpy only, so that a CSV written by any run can be analysed again).

Conventions: compression positive (stresses and strains), as in soil mechanics; axial is z. sigma1 >= sigma2 >=
sigma3 are the principal stresses; p = (sigma1 + sigma2 + sigma3) / 3, q = sigma_axial - (sigma_x + sigma_y) / 2.
The friction angles take sigma1 and sigma3 as a triaxial lab does: the axial and the lateral stress (the mean of x
and y), so that sin(phi) = 3 (q/p) / (6 + q/p) exactly. The principal values (sigma1..3_Pa) also carry the shear
stresses a periodic cell of few grains holds; they are recorded beside.
"""

import math

import numpy as np

# The columns of a record, in the order triaxial.csv writes them (units in the names).
COLUMNS = ('n', 'phase', 'step', 'time_s', 'axial_strain', 'volumetric_strain', 'sigma1_Pa', 'sigma2_Pa', 'sigma3_Pa',
           'sigma_axial_Pa', 'sigma_lateral_Pa', 'p_Pa', 'q_Pa', 'q_over_p', 'void_ratio', 'void_ratio_union',
           'coordination', 'unbalanced', 'inertial_number')

# The quasi-static bound on the inertial number I (GDR MiDi 2004; da Cruz et al. 2005: below 1e-3 the
# response no longer depends on the rate) and on the unbalanced force (YADE's unbalancedForce(): the mean
# resultant force on a body over the mean contact force).
QUASI_STATIC_I = 1e-3
QUASI_STATIC_UNBALANCED = 0.1
# The critical state: the volume no longer changes as the specimen shears, |d eps_v / d eps_a| under this.
CRITICAL_SLOPE = 0.1


def mobilized(sigma1, sigma3):
    """The mobilized friction angle, degrees, of Mohr-Coulomb without cohesion: sin(phi) = (s1 - s3) / (s1 + s3)."""
    s1, s3 = np.asarray(sigma1, dtype=float), np.asarray(sigma3, dtype=float)
    with np.errstate(divide='ignore', invalid='ignore'):
        x = np.where(s1 + s3 > 0, (s1 - s3) / (s1 + s3), np.nan)
    return np.degrees(np.arcsin(np.clip(x, -1.0, 1.0)))


def dilatancy(axial, volumetric, window):
    """The dilatancy angle, degrees, along the curve: sin(psi) = -d / (2 - d), d = d(eps_v) / d(eps_a) (eps_v
    positive in compaction; psi > 0 where the specimen dilates), each slope a least-squares fit over *window* of
    axial strain centred on the record (the records are noisy; one record's difference is not a rate).

    :return: array of psi, NaN where the window holds under 3 records
    """
    a, v = np.asarray(axial, dtype=float), np.asarray(volumetric, dtype=float)
    out = np.full(len(a), np.nan)
    for i in range(len(a)):
        m = np.abs(a - a[i]) <= 0.5 * window
        if m.sum() < 3 or np.ptp(a[m]) <= 0:
            continue
        d = np.polyfit(a[m], v[m], 1)[0]
        out[i] = math.degrees(math.asin(max(-1.0, min(1.0, -d / (2.0 - d)))))
    return out


def derived(rows):
    """The figures a triaxial curve gives: peak and critical-state friction angles, the largest dilatancy angle,
    E50, the initial void ratios, and whether the run was quasi-static.

    :param rows: the shearing records, dicts with :data:`COLUMNS` (at least axial_strain, volumetric_strain,
        sigma_axial_Pa, sigma_lateral_Pa, q_Pa, p_Pa, void_ratio, void_ratio_union, inertial_number, unbalanced), in order
    :return: dict: phi_peak_deg (the largest mobilized angle, sigma1 axial and sigma3 lateral), strain_at_peak, phi_cs_deg (the mean mobilized angle
        over the last fifth of the axial strain), dvol_rate_end (d eps_v / d eps_a there: 0 at the critical state),
        psi_max_deg (the largest dilatancy angle, slopes over windows of 1/20 of the strain, 5 records at least), E50_Pa (the secant
        modulus to half the peak deviator, from the deviator at the start of shearing), e0, e0_union, q_peak_Pa,
        p_peak_Pa, I_max, unbalanced_median, quasi_static, strain_end, peak_reached (the largest angle lies
        before the last tenth of the strain), critical_state (|dvol_rate_end| <= CRITICAL_SLOPE)
    """
    if len(rows) < 3:
        raise ValueError('triaxial: %d records of shearing: at least 3 are needed for the derived figures'
                         % len(rows))
    col = {k: np.array([float(r[k]) for r in rows]) for k in ('axial_strain', 'volumetric_strain', 'sigma_axial_Pa',
                                                              'sigma_lateral_Pa', 'q_Pa', 'p_Pa', 'void_ratio',
                                                              'void_ratio_union', 'inertial_number', 'unbalanced')}
    a, v = col['axial_strain'], col['volumetric_strain']
    phi = mobilized(col['sigma_axial_Pa'], col['sigma_lateral_Pa'])
    k = int(np.nanargmax(phi))
    span = a[-1] - a[0]
    late = a >= a[-1] - 0.2 * span
    if late.sum() >= 2 and np.ptp(a[late]) > 0:
        slopeEnd = float(np.polyfit(a[late], v[late], 1)[0])
    else:
        slopeEnd = float('nan')
    # slopes over a twentieth of the strain, and over 5 records at least
    psi = dilatancy(a, v, max(span / 20.0, 5.0 * float(np.median(np.diff(a)))))
    dq = col['q_Pa'] - col['q_Pa'][0]
    half = 0.5 * dq.max()
    j = int(np.argmax(dq >= half))
    if j == 0:
        e50 = float('nan')
    else:  # linear between the records around the crossing
        f = (half - dq[j - 1]) / (dq[j] - dq[j - 1]) if dq[j] != dq[j - 1] else 1.0
        e = (a[j - 1] + f * (a[j] - a[j - 1])) - a[0]
        e50 = float(half / e) if e > 0 else float('nan')
    iMax = float(np.nanmax(col['inertial_number']))
    unbalanced = float(np.nanmedian(col['unbalanced']))
    return dict(phi_peak_deg=float(phi[k]), strain_at_peak=float(a[k]), phi_cs_deg=float(np.nanmean(phi[late])),
                dvol_rate_end=slopeEnd, psi_max_deg=float(np.nanmax(psi)) if np.isfinite(psi).any() else float('nan'),
                E50_Pa=e50, e0=float(col['void_ratio'][0]), e0_union=float(col['void_ratio_union'][0]),
                q_peak_Pa=float(col['q_Pa'][k]), p_peak_Pa=float(col['p_Pa'][k]), I_max=iMax,
                unbalanced_median=unbalanced, strain_end=float(a[-1]),
                peak_reached=bool(a[k] < a[-1] - 0.1 * span), critical_state=bool(abs(slopeEnd) <= CRITICAL_SLOPE),
                quasi_static=bool(iMax <= QUASI_STATIC_I and unbalanced <= QUASI_STATIC_UNBALANCED))
