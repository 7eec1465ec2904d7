/* clr_film_prepare of four samples at once for host film tiles: when all four pass its checks
 * with nothing to change (every component finite, luminance finite and >= CLR_FILM_MIN_LUMINANCE,
 * no luminance clamp, L * w finite, inside the sample bounds), their prepared forms with the
 * same bits; otherwise the caller prepares them one by one (clr_film_prepare decides their drops,
 * clamps and counts). SSE2 where the compiler has it, else clr_film_prepare lane by lane. */
#ifndef CLR_FILM_SCREEN_H
#define CLR_FILM_SCREEN_H

#include <math.h>
#include "clrender/film.h"
#include "film_funcs.h"
#include "film_types.h"
#include "filter_types.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#define CLR_FILM_SCREEN_LANES 4

/* The film's bounds and limits as clr_film_prepare converts and compares them. */
typedef struct clr_film_screen {
  clr_film_params params;
  clr_filter_params filter;
  float sample_x0, sample_x1, sample_y0, sample_y1;
  float edge_x, edge_y; /* a sample exactly at the radius past the last pixel's centre */
  float clamp_above;    /* a luminance above it is clamped (+inf: never) */
} clr_film_screen;

static inline void clr_film_screen_init(clr_film_screen *sc, const clr_film_params *fp,
                                        const clr_filter_params *f) {
  sc->params = *fp;
  sc->filter = *f;
  sc->sample_x0 = (float)fp->sample_x0;
  sc->sample_x1 = (float)fp->sample_x1;
  sc->sample_y0 = (float)fp->sample_y0;
  sc->sample_y1 = (float)fp->sample_y1;
  sc->edge_x = (float)fp->pixel_x1 - 0.5f + f->radius_x;
  sc->edge_y = (float)fp->pixel_y1 - 0.5f + f->radius_y;
  sc->clamp_above = fp->clamp_luminance ? fp->max_luminance : INFINITY;
}

#if defined(__SSE2__)
/* Lanes of v whose exponent bits are all ones (Inf, NaN). */
static inline __m128i clr_screen_not_finite(__m128 v) {
  const __m128i e = _mm_set1_epi32(0x7f800000);
  return _mm_cmpeq_epi32(_mm_and_si128(_mm_castps_si128(v), e), e);
}

/* clr_film_ceil_i32 and clr_film_floor_i32 of four floats below 2^31 in magnitude. */
static inline __m128i clr_screen_ceil(__m128 v) {
  __m128i i = _mm_cvttps_epi32(v);
  return _mm_sub_epi32(i, _mm_castps_si128(_mm_cmpgt_ps(v, _mm_cvtepi32_ps(i))));
}
static inline __m128i clr_screen_floor(__m128 v) {
  __m128i i = _mm_cvttps_epi32(v);
  return _mm_add_epi32(i, _mm_castps_si128(_mm_cmplt_ps(v, _mm_cvtepi32_ps(i))));
}
#endif

/* 1 and out[0..3] when samples[0..3] all pass unchanged (see above), else 0 (out unspecified). */
static inline int clr_film_screen4(const clr_film_screen *sc, const clr_film_sample *samples,
                                   clr_film_prepared *out) {
#if defined(__SSE2__)
  const float *f = &samples[0].x; /* 4 samples x 6 floats, contiguous */
  __m128 v0 = _mm_loadu_ps(f), v1 = _mm_loadu_ps(f + 4), v2 = _mm_loadu_ps(f + 8);
  __m128 v3 = _mm_loadu_ps(f + 12), v4 = _mm_loadu_ps(f + 16), v5 = _mm_loadu_ps(f + 20);
  __m128i bad = _mm_or_si128(_mm_or_si128(clr_screen_not_finite(v0), clr_screen_not_finite(v1)),
                             _mm_or_si128(clr_screen_not_finite(v2), clr_screen_not_finite(v3)));
  bad = _mm_or_si128(bad, _mm_or_si128(clr_screen_not_finite(v4), clr_screen_not_finite(v5)));
  if (_mm_movemask_epi8(bad)) return 0;
  /* to one register per field: v0 = x0 y0 r0 g0, v1 = b0 w0 x1 y1, v2 = r1 g1 b1 w1, ... */
  __m128 xy01 = _mm_shuffle_ps(v0, v1, _MM_SHUFFLE(3, 2, 1, 0)); /* x0 y0 x1 y1 */
  __m128 xy23 = _mm_shuffle_ps(v3, v4, _MM_SHUFFLE(3, 2, 1, 0)); /* x2 y2 x3 y3 */
  __m128 x = _mm_shuffle_ps(xy01, xy23, _MM_SHUFFLE(2, 0, 2, 0));
  __m128 y = _mm_shuffle_ps(xy01, xy23, _MM_SHUFFLE(3, 1, 3, 1));
  __m128 rg01 = _mm_shuffle_ps(v0, v2, _MM_SHUFFLE(1, 0, 3, 2)); /* r0 g0 r1 g1 */
  __m128 rg23 = _mm_shuffle_ps(v3, v5, _MM_SHUFFLE(1, 0, 3, 2)); /* r2 g2 r3 g3 */
  __m128 r = _mm_shuffle_ps(rg01, rg23, _MM_SHUFFLE(2, 0, 2, 0));
  __m128 g = _mm_shuffle_ps(rg01, rg23, _MM_SHUFFLE(3, 1, 3, 1));
  __m128 bw01 = _mm_shuffle_ps(v1, v2, _MM_SHUFFLE(3, 2, 1, 0)); /* b0 w0 b1 w1 */
  __m128 bw23 = _mm_shuffle_ps(v4, v5, _MM_SHUFFLE(3, 2, 1, 0)); /* b2 w2 b3 w3 */
  __m128 b = _mm_shuffle_ps(bw01, bw23, _MM_SHUFFLE(2, 0, 2, 0));
  __m128 w = _mm_shuffle_ps(bw01, bw23, _MM_SHUFFLE(3, 1, 3, 1));
  /* clr_film_luminance, left to right */
  __m128 lum = _mm_add_ps(
      _mm_add_ps(_mm_mul_ps(_mm_set1_ps(0.212671f), r), _mm_mul_ps(_mm_set1_ps(0.715160f), g)),
      _mm_mul_ps(_mm_set1_ps(0.072169f), b));
  __m128 rw = _mm_mul_ps(r, w), gw = _mm_mul_ps(g, w), bw = _mm_mul_ps(b, w);
  __m128i drop = _mm_or_si128(clr_screen_not_finite(lum), clr_screen_not_finite(rw));
  drop = _mm_or_si128(drop, _mm_or_si128(clr_screen_not_finite(gw), clr_screen_not_finite(bw)));
  __m128 keep = _mm_andnot_ps(_mm_cmplt_ps(lum, _mm_set1_ps(CLR_FILM_MIN_LUMINANCE)),
                              _mm_cmpngt_ps(lum, _mm_set1_ps(sc->clamp_above)));
  __m128 in_x = _mm_and_ps(_mm_cmpge_ps(x, _mm_set1_ps(sc->sample_x0)),
                           _mm_or_ps(_mm_cmplt_ps(x, _mm_set1_ps(sc->sample_x1)),
                                     _mm_cmpeq_ps(x, _mm_set1_ps(sc->edge_x))));
  __m128 in_y = _mm_and_ps(_mm_cmpge_ps(y, _mm_set1_ps(sc->sample_y0)),
                           _mm_or_ps(_mm_cmplt_ps(y, _mm_set1_ps(sc->sample_y1)),
                                     _mm_cmpeq_ps(y, _mm_set1_ps(sc->edge_y))));
  keep = _mm_andnot_ps(_mm_castsi128_ps(drop), _mm_and_ps(keep, _mm_and_ps(in_x, in_y)));
  if (_mm_movemask_ps(keep) != 0xf) return 0;
  const __m128 half = _mm_set1_ps(0.5f);
  const __m128 rx = _mm_set1_ps(sc->filter.radius_x), ry = _mm_set1_ps(sc->filter.radius_y);
  __m128 dx = _mm_sub_ps(x, half), dy = _mm_sub_ps(y, half);
  float fdx[4], fdy[4], fr[4], fg[4], fb[4], fw[4];
  clr_i32 x0[4], x1[4], y0[4], y1[4];
  _mm_storeu_ps(fdx, dx);
  _mm_storeu_ps(fdy, dy);
  _mm_storeu_ps(fr, r);
  _mm_storeu_ps(fg, g);
  _mm_storeu_ps(fb, b);
  _mm_storeu_ps(fw, w);
  _mm_storeu_si128((__m128i *)x0, clr_screen_ceil(_mm_sub_ps(dx, rx)));
  _mm_storeu_si128((__m128i *)x1, clr_screen_floor(_mm_add_ps(dx, rx)));
  _mm_storeu_si128((__m128i *)y0, clr_screen_ceil(_mm_sub_ps(dy, ry)));
  _mm_storeu_si128((__m128i *)y1, clr_screen_floor(_mm_add_ps(dy, ry)));
  for (int k = 0; k < CLR_FILM_SCREEN_LANES; ++k) {
    clr_film_prepared *s = &out[k];
    s->dx = fdx[k];
    s->dy = fdy[k];
    s->r = fr[k];
    s->g = fg[k];
    s->b = fb[k];
    s->w = fw[k];
    s->x0 = x0[k];
    s->x1 = x1[k];
    s->y0 = y0[k];
    s->y1 = y1[k];
  }
  return 1;
#else
  int all = 1;
  for (int k = 0; k < CLR_FILM_SCREEN_LANES; ++k) {
    const clr_film_sample *in = &samples[k];
    all &= clr_film_prepare(&sc->params, &sc->filter, in->x, in->y, in->r, in->g, in->b, in->weight,
                            &out[k]) == CLR_FILM_SAMPLE_OK;
  }
  return all;
#endif
}

#endif
