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

void clr_wave_ao_directions(int32_t n, const float frame[9], float count, float *restrict x,
                            float *restrict y, float *restrict z, float *restrict cos_n,
                            float *restrict term) {
  const float *ss = frame, *ts = frame + 3, *nn = frame + 6;
  for (int32_t k = 0; k < n; ++k) {
    float w0 = x[k], w1 = y[k], w2 = z[k];
    float wx = ss[0] * w0 + ts[0] * w1 + nn[0] * w2, wy = ss[1] * w0 + ts[1] * w1 + nn[1] * w2,
          wz = ss[2] * w0 + ts[2] * w1 + nn[2] * w2;
    float pdf = fabsf(w2) * RS_INV_PI, c = wx * nn[0] + wy * nn[1] + wz * nn[2];
    x[k] = wx;
    y[k] = wy;
    z[k] = wz;
    cos_n[k] = c;
    term[k] = pdf > 0.0f ? c / (pdf * count) : 0.0f;
  }
}
