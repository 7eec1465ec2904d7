/* pbrt-v3's "blackbody" spectra (BlackbodyNormalized: Planck's law divided by its value at the
 * peak wavelength of Wien's law) converted to linear sRGB as pbrt-v3's RGBSpectrum::FromSampled
 * does (XYZ summed over 360..830 nm at 1 nm, normalized by the Y integral, then its XYZToRGB),
 * with the CIE 1931 matching functions given by Wyman, Sloan and Shirley's multi-lobe analytic
 * fit (JCGT 2013) instead of the tabulated CIE data. */
#ifndef CLR_RENDER_BLACKBODY_H
#define CLR_RENDER_BLACKBODY_H

/* RGB of the normalized blackbody at temperature t (Kelvin); 0 for t <= 0. */
void rs_blackbody_rgb(float t, float rgb[3]);

#endif
