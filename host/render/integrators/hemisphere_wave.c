/* The cosine-hemisphere wave: both sides of the concentric disk's branch computed, then
 * selected (the same operations as the scalar code's taken side). */
#include "hemisphere_wave.h"
#include <math.h>
#include "vec3.h"

/* clr_cosine_hemisphere: the concentric disk's one division picks its operands first; a point
 * at the disk's centre gets (0, 0) (its division by 1 is discarded). */
void clr_wave_cosine_hemisphere(int32_t n, const float *restrict u0, const float *restrict u1,
                                float *restrict x, float *restrict y, float *restrict z) {
  for (int32_t k = 0; k < n; ++k) {
    float ox = 2.0f * u0[k] - 1.0f, oy = 2.0f * u1[k] - 1.0f;
    int centre = ox == 0.0f && oy == 0.0f, wide = fabsf(ox) > fabsf(oy);
    float num = wide ? oy : ox, den = wide ? ox : oy;
    float a = (RS_PI / 4.0f) * (num / (centre ? 1.0f : den));
    float a2 = a * a;
    float sn =
        a * (1.0f + a2 * (-1.0f / 6.0f +
                          a2 * (1.0f / 120.0f + a2 * (-1.0f / 5040.0f + a2 * (1.0f / 362880.0f)))));
    float cs =
        1.0f + a2 * (-0.5f + a2 * (1.0f / 24.0f +
                                   a2 * (-1.0f / 720.0f +
                                         a2 * (1.0f / 40320.0f + a2 * (-1.0f / 3628800.0f)))));
    float px = den * (wide ? cs : sn), py = den * (wide ? sn : cs);
    px = centre ? 0.0f : px;
    py = centre ? 0.0f : py;
    float z2 = 1.0f - px * px - py * py;
    x[k] = px;
    y[k] = py;
    z[k] = sqrtf(z2 > 0.0f ? z2 : 0.0f);
  }
}
