"""Reflection: Fresnel, Cox-Munk sea (eq. 7), RPV land (eq. 8), Cook-Torrance paint (eq. 19).

Conventions (all public functions): angles in degrees in the surface's local frame (z =
surface normal), as everywhere else in the project (the kernels work in radians inside).
``theta_i, phi_i`` are the zenith and azimuth of the direction *toward the source* (sun, sky
patch), ``theta_r, phi_r`` of the direction *toward the viewer*; both point away from the
surface. The specular direction of ``(theta_i, phi_i)`` is ``(theta_i, phi_i + 180)``; the
backscatter (hot-spot) direction is ``(theta_i, phi_i)``.
Every BRDF returns ``f_r`` in [sr-1] (reflected radiance per unit incident irradiance on the
surface), zero when either direction is below the surface, and broadcasts over arrays.
:func:`directional_albedo` integrates any of them over the view hemisphere.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import erfc

from shipthermal.errors import InputError, check_positive, check_range, require
from .water import fresnel_reflectance  # the one Fresnel reflectance
from shipthermal.parameters import check_wind_speed

from .quadrature import gauss_legendre

__all__ = [
    "direction", "fresnel_reflectance", "fresnel_normal_reflectance", "schlick_fresnel",
    "cox_munk_slope_variance", "cox_munk_brdf", "smith_lambda_gaussian",
    "rpv_brdf", "cook_torrance_brdf", "cook_torrance_brdf_vectors", "directional_albedo",
]


def direction(theta, phi):
    """Unit vector(s) [-] for zenith ``theta`` [deg] and azimuth ``phi`` [deg], shape (..., 3)."""
    return _direction(np.radians(theta), np.radians(phi))


def _direction(theta, phi):
    """:func:`direction` with angles in radians."""
    theta = np.asarray(theta, dtype=float)
    phi = np.asarray(phi, dtype=float)
    st = np.sin(theta)
    return np.stack(np.broadcast_arrays(st * np.cos(phi), st * np.sin(phi), np.cos(theta)),
                    axis=-1)


# ---------------------------------------------------------------------------------------
# Fresnel
# ---------------------------------------------------------------------------------------
def fresnel_normal_reflectance(refractive_index):
    """Normal-incidence reflectance ``((n-1)^2 + k^2) / ((n+1)^2 + k^2)`` [-] (``F0``)."""
    m = np.asarray(refractive_index, dtype=complex)
    return np.abs((m - 1.0) / (m + 1.0)) ** 2


def schlick_fresnel(cos_incidence, f0):
    """Schlick (1994) approximation ``F0 + (1 - F0)(1 - cos)^5`` [-].

    ``cos_incidence`` [-], ``f0`` normal-incidence reflectance [-].
    """
    ci = np.clip(np.asarray(cos_incidence, dtype=float), 0.0, 1.0)
    return f0 + (1.0 - f0) * (1.0 - ci) ** 5


# ---------------------------------------------------------------------------------------
# Cox-Munk sea surface
# ---------------------------------------------------------------------------------------
_CALM_COMPONENT_FLOOR = 0.0015  # half of Cox & Munk's calm-sea 0.003: keeps variances > 0


def cox_munk_slope_variance(wind_speed, anisotropic: bool = False):
    """Sea-surface slope variances of Cox & Munk (1954), clean sea.

    Parameters
    ----------
    wind_speed : array_like
        Wind speed at 12.5 m above the sea [m s-1] (10 m wind is within the fit's scatter).
    anisotropic : bool
        False: total mean-square slope ``sigma^2 = 0.003 + 5.12e-3 U``.
        True: ``(sigma_u^2, sigma_c^2) = (3.16e-3 U, 0.003 + 1.92e-3 U)`` up- and cross-wind.

    Returns
    -------
    numpy.ndarray or tuple
        Mean-square slope(s) [-].

    Notes
    -----
    Cox, C. & Munk, W. (1954), J. Opt. Soc. Am. 44:838-850 and J. Mar. Res. 13:198-227
    (fits for 1-14 m/s). The up-wind variance vanishes at zero wind in the fit; each
    component is floored at 0.0015 (half the calm isotropic 0.003) so the density stays
    defined.
    """
    u = np.asarray(wind_speed, dtype=float)
    check_wind_speed("wind_speed", u)
    if not anisotropic:
        return 0.003 + 5.12e-3 * u
    return (np.maximum(3.16e-3 * u, _CALM_COMPONENT_FLOOR),
            np.maximum(0.003 + 1.92e-3 * u, _CALM_COMPONENT_FLOOR))


def smith_lambda_gaussian(cot_theta, sigma_component):
    """Smith (1967) shadowing term Lambda for Gaussian slopes [-].

    ``cot_theta`` [-] is the cotangent of the direction's zenith angle, ``sigma_component``
    [-] the rms slope along the direction's azimuth. With ``a = cot / (sqrt 2 sigma)``:
    ``Lambda = (exp(-a^2) / (a sqrt pi) - erfc(a)) / 2``. Smith, B. G. (1967), IEEE Trans.
    Antennas Propag. 15:668.
    """
    a = np.asarray(cot_theta, dtype=float) / (math.sqrt(2.0) * sigma_component)
    a = np.clip(a, 1e-12, 1e150)  # upper clip: avoid overflow of a*a at normal incidence
    return 0.5 * (np.exp(-a * a) / (a * math.sqrt(math.pi)) - erfc(a))


def cox_munk_brdf(theta_i, phi_i, theta_r, phi_r, wind_speed, refractive_index=1.33 + 0j,
                  wind_azimuth=None, shadowing: bool = False):
    """Sea-surface BRDF from Cox-Munk facet slopes (paper eq. 7).

    Parameters
    ----------
    theta_i, phi_i : array_like
        Zenith and azimuth of the direction to the sun [deg].
    theta_r, phi_r : array_like
        Zenith and azimuth of the direction to the sensor [deg].
    wind_speed : float
        Wind speed [m s-1] (see :func:`cox_munk_slope_variance`).
    refractive_index : complex
        Complex refractive index of water in the band [-] (e.g.
        :func:`shipthermal.optics.sea.water_band_mean_index`); default 1.33 (visible).
    wind_azimuth : float or None
        None: isotropic slopes. Otherwise the azimuth of the wind axis in the same frame as
        ``phi`` [deg]: anisotropic up/cross-wind Gaussian.
    shadowing : bool
        Apply Smith's bidirectional shadowing ``1 / (1 + Lambda_i + Lambda_r)``.

    Returns
    -------
    numpy.ndarray
        BRDF [sr-1].

    Notes
    -----
    ``f = rho(omega) P(z_x, z_y) / (4 cos(theta_i) cos(theta_r) cos^4 beta)``, with the
    facet normal the half vector of sun and view directions, ``beta`` its tilt,
    ``omega`` the local incidence angle and ``P`` the slope density. The paper's eq. 7,
    ``pi P rho / (4 cos theta_r cos^4 beta)``, is ``pi cos(theta_i) f`` (a reflectance
    factor per unit normal-beam irradiance); this module returns the BRDF proper so that
    eq. 2's ``E cos(theta_i) BRDF`` is right.
    Without shadowing the hemispherical integral can slightly exceed the Fresnel
    reflectance at grazing sun because facets facing away from the sun are not removed.
    """
    return _cox_munk_brdf(np.radians(theta_i), np.radians(phi_i), np.radians(theta_r),
                          np.radians(phi_r), wind_speed, refractive_index,
                          None if wind_azimuth is None else math.radians(wind_azimuth),
                          shadowing)


def _cox_munk_brdf(theta_i, phi_i, theta_r, phi_r, wind_speed, refractive_index=1.33 + 0j,
                   wind_azimuth=None, shadowing: bool = False):
    """:func:`cox_munk_brdf` with angles in radians."""
    mu_i = np.cos(np.asarray(theta_i, dtype=float))
    mu_r = np.cos(np.asarray(theta_r, dtype=float))
    s = _direction(theta_i, phi_i)
    v = _direction(theta_r, phi_r)
    h = s + v
    h = h / np.linalg.norm(h, axis=-1, keepdims=True)
    hz = np.maximum(h[..., 2], 1e-12)
    zx, zy = -h[..., 0] / hz, -h[..., 1] / hz
    if wind_azimuth is None:
        var = cox_munk_slope_variance(wind_speed)
        prob = np.exp(-(zx * zx + zy * zy) / var) / (math.pi * var)
        sig_i = sig_r = math.sqrt(var / 2.0)
    else:
        var_u, var_c = cox_munk_slope_variance(wind_speed, anisotropic=True)
        cw, sw = math.cos(wind_azimuth), math.sin(wind_azimuth)
        zu, zc = zx * cw + zy * sw, -zx * sw + zy * cw
        prob = (np.exp(-0.5 * (zu * zu / var_u + zc * zc / var_c))
                / (2.0 * math.pi * math.sqrt(var_u * var_c)))
        dpi = np.asarray(phi_i, dtype=float) - wind_azimuth
        dpr = np.asarray(phi_r, dtype=float) - wind_azimuth
        sig_i = np.sqrt(var_u * np.cos(dpi) ** 2 + var_c * np.sin(dpi) ** 2)
        sig_r = np.sqrt(var_u * np.cos(dpr) ** 2 + var_c * np.sin(dpr) ** 2)
    cos_omega = np.sum(s * h, axis=-1)
    rho = fresnel_reflectance(cos_omega, refractive_index)
    up = (mu_i > 0) & (mu_r > 0)
    denom = 4.0 * np.where(up, mu_i * mu_r, 1.0) * hz**4
    f = np.where(up, rho * prob / denom, 0.0)
    if shadowing:
        cot_i = mu_i / np.maximum(np.sqrt(1 - mu_i**2), 1e-12)
        cot_r = mu_r / np.maximum(np.sqrt(1 - mu_r**2), 1e-12)
        f = f / (1.0 + smith_lambda_gaussian(cot_i, sig_i) + smith_lambda_gaussian(cot_r, sig_r))
    return f


# ---------------------------------------------------------------------------------------
# RPV land
# ---------------------------------------------------------------------------------------
def rpv_brdf(theta_i, phi_i, theta_r, phi_r, rho0, k, b, rho_c=None, phase: str = "exp"):
    """Rahman-Pinty-Verstraete land BRDF (paper eq. 8).

    Parameters
    ----------
    theta_i, phi_i, theta_r, phi_r : array_like
        Sun and view directions [deg] (module conventions).
    rho0 : float
        Amplitude (reflectance level) [-].
    k : float
        Minnaert-like anisotropy exponent [-] (k < 1 bowl-shaped, k > 1 bell-shaped).
    b : float
        Phase parameter [-]: ``b`` of ``exp(b cos xi)`` (``phase="exp"``, the modified RPV of
        the paper's eq. 8) or the Henyey-Greenstein ``Theta`` (``phase="hg"``, ``|Theta| < 1``,
        original RPV). Negative values favour backscattering in both cases.
    rho_c : float or None
        Hot-spot parameter [-]; default ``rho0`` (original RPV).
    phase : {"exp", "hg"}
        Phase-function form.

    Returns
    -------
    numpy.ndarray
        BRDF [sr-1] = reflectance factor / pi.

    Notes
    -----
    Rahman, Pinty & Verstraete (1993), J. Geophys. Res. 98(D11):20791-20801; modified
    exponential phase: Engelsen, Pinty, Verstraete & Martonchik (1996), EUR 16426 EN.
    ``BRF = rho0 M(k) F(xi) H``, with
    ``M = cos^{k-1}(theta_i) cos^{k-1}(theta_r) / (cos theta_i + cos theta_r)^{1-k}``
    (the paper's eq. 8 lost the products in typesetting), ``cos xi = -cos theta_i cos
    theta_r - sin theta_i sin theta_r cos(phi_r - phi_i)`` the scattering angle (xi = pi at
    the hot spot), and the hot-spot term ``H = 1 + (1 - rho_c) / (1 + G)`` with
    ``G = sqrt(tan^2 theta_i + tan^2 theta_r - 2 tan theta_i tan theta_r cos(phi_r - phi_i))``
    (G = 0 at the hot spot). Every factor is symmetric in (i, r): reciprocal by construction.
    """
    return _rpv_brdf(np.radians(theta_i), np.radians(phi_i), np.radians(theta_r),
                     np.radians(phi_r), rho0, k, b, rho_c, phase)


def _rpv_brdf(theta_i, phi_i, theta_r, phi_r, rho0, k, b, rho_c=None, phase: str = "exp"):
    """:func:`rpv_brdf` with angles in radians."""
    ti = np.asarray(theta_i, dtype=float)
    tr = np.asarray(theta_r, dtype=float)
    mu_i, mu_r = np.cos(ti), np.cos(tr)
    up = (mu_i > 0) & (mu_r > 0)
    mi, mr = np.where(up, mu_i, 1.0), np.where(up, mu_r, 1.0)
    cphi = np.cos(np.asarray(phi_r, dtype=float) - np.asarray(phi_i, dtype=float))
    minnaert = (mi * mr) ** (k - 1.0) / (mi + mr) ** (1.0 - k)
    cos_xi = -mi * mr - np.sin(ti) * np.sin(tr) * cphi
    if phase == "exp":
        fphase = np.exp(b * cos_xi)
    elif phase == "hg":
        require(abs(b) < 1, "b", b, "Henyey-Greenstein Theta must satisfy |Theta| < 1")
        fphase = (1.0 - b * b) / (1.0 + b * b - 2.0 * b * cos_xi) ** 1.5
    else:
        raise InputError("phase", phase, "must be 'exp' or 'hg'")
    tan_i = np.sqrt(1.0 - mi**2) / mi
    tan_r = np.sqrt(1.0 - mr**2) / mr
    g = np.sqrt(np.maximum(tan_i**2 + tan_r**2 - 2.0 * tan_i * tan_r * cphi, 0.0))
    rc = rho0 if rho_c is None else rho_c
    hot = 1.0 + (1.0 - rc) / (1.0 + g)
    return np.where(up, rho0 * minnaert * fphase * hot / math.pi, 0.0)


# ---------------------------------------------------------------------------------------
# Cook-Torrance ship paint
# ---------------------------------------------------------------------------------------
def _microfacet_d(cos_h, roughness, distribution):
    c2 = np.maximum(cos_h, 1e-12) ** 2
    a2 = roughness * roughness
    if distribution == "beckmann":
        tan2 = (1.0 - c2) / c2
        return np.exp(-tan2 / a2) / (math.pi * a2 * c2 * c2)
    if distribution == "ggx":
        return a2 / (math.pi * (c2 * (a2 - 1.0) + 1.0) ** 2)
    raise InputError("distribution", distribution, "must be 'beckmann' or 'ggx'")


def _smith_lambda(cos_t, roughness, distribution):
    c = np.clip(cos_t, 1e-12, 1.0)
    tan_t = np.sqrt(1.0 - c * c) / c
    if distribution == "beckmann":
        # Beckmann with rms slope m is a Gaussian with per-axis sigma = m / sqrt 2
        return smith_lambda_gaussian(1.0 / np.maximum(tan_t, 1e-300), roughness / math.sqrt(2.0))
    return 0.5 * (-1.0 + np.sqrt(1.0 + (roughness * tan_t) ** 2))


def cook_torrance_brdf_vectors(normal, to_light, to_view, roughness, kd, ks,
                               refractive_index=None, f0=None, distribution: str = "beckmann",
                               fresnel: str = "exact", geometry: str = "smith"):
    """Cook-Torrance BRDF for arbitrary normals (paper eq. 19), vector form.

    Parameters
    ----------
    normal, to_light, to_view : array_like
        Unit vectors [-], shape (..., 3): surface normal, direction to the source, direction
        to the viewer.
    roughness : float
        Beckmann rms slope ``m`` or GGX ``alpha`` [-], > 0.
    kd, ks : float
        Diffuse albedo and specular weight [-]; ``kd + ks <= 1`` keeps the albedo <= 1.
    refractive_index : complex or None
        Paint's complex index [-] for the Fresnel term (exact, or to derive ``f0``).
    f0 : float or None
        Normal-incidence reflectance [-] (Schlick only), if no index is given.
    distribution : {"beckmann", "ggx"}
        Micro-facet normal distribution D.
    fresnel : {"exact", "schlick"}
        Fresnel term F at the micro-facet incidence ``l . h``.
    geometry : {"smith", "cook-torrance"}
        Shadowing-masking G: height-correlated Smith ``1 / (1 + Lambda_l + Lambda_v)`` or the
        original V-cavity ``min(1, 2 nh nv / vh, 2 nh nl / vh)``.

    Returns
    -------
    numpy.ndarray
        BRDF [sr-1].

    Notes
    -----
    ``f = kd / pi + ks F D G / (4 (n.l)(n.v))`` with D normalised so that
    ``int D (n.h) d omega = 1``. Cook & Torrance (1982), ACM TOG 1:7-24 (their D lacks the
    1/pi, hence the ``pi`` in their and the paper's eq. 19 denominator; eq. 19's light
    intensity ``I_l`` and ``(n.l)`` factor belong to the radiance, not to the BRDF).
    Walter et al. (2007) for GGX and Smith; Heitz (2014), JCGT 3(2), for Lambda.
    """
    check_positive("roughness", roughness)
    check_range("kd", kd, 0.0, 1.0)
    check_range("ks", ks, 0.0, 1.0)
    n = np.asarray(normal, dtype=float)
    l = np.asarray(to_light, dtype=float)
    v = np.asarray(to_view, dtype=float)
    h = l + v
    h = h / np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), 1e-300)
    nl, nv = np.sum(n * l, -1), np.sum(n * v, -1)
    nh, vh = np.sum(n * h, -1), np.sum(v * h, -1)
    up = (nl > 0) & (nv > 0)
    nl_s, nv_s = np.where(up, nl, 1.0), np.where(up, nv, 1.0)
    d = _microfacet_d(nh, roughness, distribution)
    if fresnel == "exact":
        require(refractive_index is not None, "refractive_index", refractive_index,
                "is needed for fresnel='exact'")
        f = fresnel_reflectance(vh, refractive_index)
    elif fresnel == "schlick":
        if f0 is None:
            require(refractive_index is not None, "f0", f0,
                    "give f0 or refractive_index for fresnel='schlick'")
            f0 = fresnel_normal_reflectance(refractive_index)
        f = schlick_fresnel(vh, f0)
    else:
        raise InputError("fresnel", fresnel, "must be 'exact' or 'schlick'")
    if geometry == "smith":
        g = 1.0 / (1.0 + _smith_lambda(nl_s, roughness, distribution)
                   + _smith_lambda(nv_s, roughness, distribution))
    elif geometry == "cook-torrance":
        vh_s = np.maximum(vh, 1e-12)
        g = np.minimum(1.0, np.minimum(2 * nh * nv_s / vh_s, 2 * nh * nl_s / vh_s))
    else:
        raise InputError("geometry", geometry, "must be 'smith' or 'cook-torrance'")
    spec = f * d * g / (4.0 * nl_s * nv_s)
    return np.where(up, kd / math.pi + ks * spec, 0.0)


def cook_torrance_brdf(theta_i, phi_i, theta_r, phi_r, roughness, kd, ks, **kwargs):
    """Cook-Torrance BRDF [sr-1] in local angles [deg] (normal = z); see
    :func:`cook_torrance_brdf_vectors` for the parameters and equations (paper eq. 19)."""
    shape = np.broadcast_shapes(*(np.shape(a) for a in (theta_i, phi_i, theta_r, phi_r)))
    l = np.broadcast_to(direction(theta_i, phi_i), shape + (3,))
    v = np.broadcast_to(direction(theta_r, phi_r), shape + (3,))
    return cook_torrance_brdf_vectors(np.array([0.0, 0.0, 1.0]), l, v, roughness, kd, ks,
                                      **kwargs)


# ---------------------------------------------------------------------------------------
# Hemispherical integral
# ---------------------------------------------------------------------------------------
def directional_albedo(brdf, theta_i, phi_i: float = 0.0, n_mu: int = 256, n_phi: int = 512,
                       method: str = "view", **params):
    """Directional-hemispherical reflectance ``int f_r cos(theta_r) d omega_r`` [-].

    Parameters
    ----------
    brdf : callable
        ``brdf(theta_i, phi_i, theta_r, phi_r, **params)`` with angles in degrees returning
        [sr-1] (the BRDFs of this module).
    theta_i, phi_i : float
        Incidence zenith and azimuth [deg].
    n_mu : int
        Nodes in the polar variable [-]: Gauss-Legendre in ``mu = cos(theta_r)`` on [0, 1]
        (``method="view"``) or in ``t`` with half-vector zenith ``theta_h = (pi/2) t^2``
        (``method="half"``, clusters nodes around the specular direction).
    n_phi : int
        Uniform (periodic trapezoid, spectrally accurate) nodes in azimuth [-].
    method : {"view", "half"}
        Integrate over view directions, or over half vectors ``h`` with
        ``d omega_r = 4 (l.h) d omega_h`` and ``v = 2 (l.h) h - l`` (directions with
        ``v`` below the horizon contribute 0). "half" resolves narrow specular lobes.
    **params
        Passed to ``brdf``.

    Returns
    -------
    float
        Albedo [-]. By reciprocity (Helmholtz) it is also the hemispherical-directional
        reflectance for isotropic sky light seen from ``theta_i``.
    """
    require(callable(brdf), "brdf", brdf, "must be a function of (theta_i, phi_i, theta_r, "
            "phi_r, **params) [deg]")
    deg_i, deg_phi_i = theta_i, phi_i
    theta_i, phi_i = math.radians(theta_i), math.radians(phi_i)
    x, w = gauss_legendre(int(n_mu))
    if method == "view":
        mu = 0.5 * (x + 1.0)
        wmu = 0.5 * w
        phi = phi_i + 2.0 * math.pi * np.arange(n_phi) / n_phi
        theta_r = np.arccos(mu)[:, None]
        f = brdf(deg_i, deg_phi_i, np.degrees(theta_r), np.degrees(phi[None, :]), **params)
        return float(np.sum(wmu[:, None] * mu[:, None] * f) * 2.0 * math.pi / n_phi)
    if method != "half":
        raise InputError("method", method, "must be 'view' or 'half'")
    t = 0.5 * (x + 1.0)
    theta_h = 0.5 * math.pi * t * t
    wth = 0.5 * w * math.pi * t            # d theta_h = pi t dt, dt = dx / 2
    # half vectors around the specular direction of l (azimuth phi_i + pi, zenith 0 = normal)
    phi_h = phi_i + 2.0 * math.pi * np.arange(n_phi) / n_phi
    h = _direction(theta_h[:, None], phi_h[None, :])
    l = _direction(theta_i, phi_i)
    lh = h @ l
    v = 2.0 * lh[..., None] * h - l
    vz = v[..., 2]
    ok = (lh > 0) & (vz > 0)
    theta_r = np.arccos(np.clip(vz, -1.0, 1.0))
    phi_r = np.arctan2(v[..., 1], v[..., 0])
    f = np.where(ok, brdf(deg_i, deg_phi_i, np.degrees(theta_r), np.degrees(phi_r), **params),
                 0.0)
    integrand = f * np.where(ok, vz, 0.0) * 4.0 * np.maximum(lh, 0.0) * np.sin(theta_h)[:, None]
    return float(np.sum(wth[:, None] * integrand) * 2.0 * math.pi / n_phi)
