/* clr_film_prepare of four samples at once for host film tiles and the film's binning (pass 1):
 * when all four pass its checks with nothing to change (every component finite, luminance finite
 * and >= CLR_FILM_MIN_LUMINANCE, no luminance clamp, L * w finite, inside the sample bounds), their
 * prepared forms with the same bits; otherwise the caller prepares them one by one
 * (clr_film_prepare decides their drops, clamps and counts). SSE2 where the compiler has it (its
 * pieces, clr_screen_*, for callers that keep the lanes), else clr_film_prepare lane by lane. */
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

/* The screen's limits, four lanes each (set once for many groups). */
typedef struct clr_screen_limits {
  __m128 sample_x0, sample_x1, sample_y0, sample_y1, edge_x, edge_y, clamp_above;
  __m128 radius_x, radius_y;
} clr_screen_limits;

static inline clr_screen_limits clr_screen_limits_of(const clr_film_screen *sc) {
  clr_screen_limits l;
  l.sample_x0 = _mm_set1_ps(sc->sample_x0);
  l.sample_x1 = _mm_set1_ps(sc->sample_x1);
  l.sample_y0 = _mm_set1_ps(sc->sample_y0);
  l.sample_y1 = _mm_set1_ps(sc->sample_y1);
  l.edge_x = _mm_set1_ps(sc->edge_x);
  l.edge_y = _mm_set1_ps(sc->edge_y);
  l.clamp_above = _mm_set1_ps(sc->clamp_above);
  l.radius_x = _mm_set1_ps(sc->filter.radius_x);
  l.radius_y = _mm_set1_ps(sc->filter.radius_y);
  return l;
}

/* samples[0..3]'s floats as loaded, six registers: v[0] = x0 y0 r0 g0, v[1] = b0 w0 x1 y1,
 * v[2] = r1 g1 b1 w1, v[3..5] the same for samples 2 and 3; 0 when a component is not finite. */
static inline int clr_screen_load(const clr_film_sample *samples, __m128 v[6]) {
  const float *f = &samples[0].x; /* 4 samples x 6 floats, contiguous */
  for (int k = 0; k < 6; ++k) v[k] = _mm_loadu_ps(f + 4 * k);
  __m128i bad =
      _mm_or_si128(_mm_or_si128(clr_screen_not_finite(v[0]), clr_screen_not_finite(v[1])),
                   _mm_or_si128(clr_screen_not_finite(v[2]), clr_screen_not_finite(v[3])));
  bad = _mm_or_si128(bad, _mm_or_si128(clr_screen_not_finite(v[4]), clr_screen_not_finite(v[5])));
  return !_mm_movemask_epi8(bad);
}

/* Four samples' fields, one register each (lane k: sample k). */
typedef struct clr_screen_fields {
  __m128 x, y, r, g, b, w;
} clr_screen_fields;

static inline clr_screen_fields clr_screen_transpose(const __m128 v[6]) {
  clr_screen_fields f;
  __m128 xy01 = _mm_shuffle_ps(v[0], v[1], _MM_SHUFFLE(3, 2, 1, 0)); /* x0 y0 x1 y1 */
  __m128 xy23 = _mm_shuffle_ps(v[3], v[4], _MM_SHUFFLE(3, 2, 1, 0)); /* x2 y2 x3 y3 */
  f.x = _mm_shuffle_ps(xy01, xy23, _MM_SHUFFLE(2, 0, 2, 0));
  f.y = _mm_shuffle_ps(xy01, xy23, _MM_SHUFFLE(3, 1, 3, 1));
  __m128 rg01 = _mm_shuffle_ps(v[0], v[2], _MM_SHUFFLE(1, 0, 3, 2)); /* r0 g0 r1 g1 */
  __m128 rg23 = _mm_shuffle_ps(v[3], v[5], _MM_SHUFFLE(1, 0, 3, 2)); /* r2 g2 r3 g3 */
  f.r = _mm_shuffle_ps(rg01, rg23, _MM_SHUFFLE(2, 0, 2, 0));
  f.g = _mm_shuffle_ps(rg01, rg23, _MM_SHUFFLE(3, 1, 3, 1));
  __m128 bw01 = _mm_shuffle_ps(v[1], v[2], _MM_SHUFFLE(3, 2, 1, 0)); /* b0 w0 b1 w1 */
  __m128 bw23 = _mm_shuffle_ps(v[4], v[5], _MM_SHUFFLE(3, 2, 1, 0)); /* b2 w2 b3 w3 */
  f.b = _mm_shuffle_ps(bw01, bw23, _MM_SHUFFLE(2, 0, 2, 0));
  f.w = _mm_shuffle_ps(bw01, bw23, _MM_SHUFFLE(3, 1, 3, 1));
  return f;
}

/* Whether four finite samples all pass clr_film_prepare's remaining checks with nothing to
 * change. */
static inline int clr_screen_plain(const clr_screen_limits *l, const clr_screen_fields *f) {
  /* clr_film_luminance, left to right */
  __m128 lum = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(0.212671f), f->r),
                                     _mm_mul_ps(_mm_set1_ps(0.715160f), f->g)),
                          _mm_mul_ps(_mm_set1_ps(0.072169f), f->b));
  __m128 rw = _mm_mul_ps(f->r, f->w), gw = _mm_mul_ps(f->g, f->w), bw = _mm_mul_ps(f->b, f->w);
  __m128i drop = _mm_or_si128(clr_screen_not_finite(lum), clr_screen_not_finite(rw));
  drop = _mm_or_si128(drop, _mm_or_si128(clr_screen_not_finite(gw), clr_screen_not_finite(bw)));
  __m128 keep = _mm_andnot_ps(_mm_cmplt_ps(lum, _mm_set1_ps(CLR_FILM_MIN_LUMINANCE)),
                              _mm_cmpngt_ps(lum, l->clamp_above));
  __m128 in_x =
      _mm_and_ps(_mm_cmpge_ps(f->x, l->sample_x0),
                 _mm_or_ps(_mm_cmplt_ps(f->x, l->sample_x1), _mm_cmpeq_ps(f->x, l->edge_x)));
  __m128 in_y =
      _mm_and_ps(_mm_cmpge_ps(f->y, l->sample_y0),
                 _mm_or_ps(_mm_cmplt_ps(f->y, l->sample_y1), _mm_cmpeq_ps(f->y, l->edge_y)));
  keep = _mm_andnot_ps(_mm_castsi128_ps(drop), _mm_and_ps(keep, _mm_and_ps(in_x, in_y)));
  return _mm_movemask_ps(keep) == 0xf;
}

/* Four samples' pFilmDiscrete and reached pixels, as clr_film_prepare computes them. */
typedef struct clr_screen_footprint {
  __m128 dx, dy;
  __m128i x0, x1, y0, y1;
} clr_screen_footprint;

static inline clr_screen_footprint clr_screen_reach(const clr_screen_limits *l, __m128 x,
                                                    __m128 y) {
  const __m128 half = _mm_set1_ps(0.5f), rx = l->radius_x, ry = l->radius_y;
  clr_screen_footprint p;
  p.dx = _mm_sub_ps(x, half);
  p.dy = _mm_sub_ps(y, half);
  p.x0 = clr_screen_ceil(_mm_sub_ps(p.dx, rx));
  p.x1 = clr_screen_floor(_mm_add_ps(p.dx, rx));
  p.y0 = clr_screen_ceil(_mm_sub_ps(p.dy, ry));
  p.y1 = clr_screen_floor(_mm_add_ps(p.dy, ry));
  return p;
}
#endif

/* 1 and out[0..3] when samples[0..3] all pass unchanged (see above), else 0 (out unspecified). */
static inline int clr_film_screen4(const clr_film_screen *sc, const clr_film_sample *samples,
                                   clr_film_prepared *out) {
#if defined(__SSE2__)
  __m128 v[6];
  if (!clr_screen_load(samples, v)) return 0;
  clr_screen_fields f = clr_screen_transpose(v);
  const clr_screen_limits l = clr_screen_limits_of(sc);
  if (!clr_screen_plain(&l, &f)) return 0;
  clr_screen_footprint p = clr_screen_reach(&l, f.x, f.y);
  float fdx[4], fdy[4], fr[4], fg[4], fb[4], fw[4];
  clr_i32 x0[4], x1[4], y0[4], y1[4];
  _mm_storeu_ps(fdx, p.dx);
  _mm_storeu_ps(fdy, p.dy);
  _mm_storeu_ps(fr, f.r);
  _mm_storeu_ps(fg, f.g);
  _mm_storeu_ps(fb, f.b);
  _mm_storeu_ps(fw, f.w);
  _mm_storeu_si128((__m128i *)x0, p.x0);
  _mm_storeu_si128((__m128i *)x1, p.x1);
  _mm_storeu_si128((__m128i *)y0, p.y0);
  _mm_storeu_si128((__m128i *)y1, p.y1);
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
