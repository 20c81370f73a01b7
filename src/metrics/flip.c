/* flip.c: LDR-FLIP (Andersson et al., HPG 2020). See flip.h and docs/metrics.md "FLIP".
 *
 * Constants and kernel construction as in NVlabs/flip v1.6 (BSD-3-Clause). The aim is agreement
 * with the official tool to float rounding, so every quantity is a float, every expression keeps
 * the tool's order of operations (float addition is not associative: a reordered sum moves the
 * last bits, and powf near 0 amplifies them), sums run over the kernel from left to right, and the
 * borders clamp to the edge pixel as the tool's convolutions do.
 *
 * Both 2D filters are applied as two 1D passes (x, then y). The colour filter of the blue-yellow
 * channel is a sum of two Gaussians, which is not separable as such; it is run as two separable
 * Gaussians whose results are added (the tool's separatedConvolutions.pdf).
 */
#include "metrics/flip.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#define FLIP_PI 3.14159265358979f

/* The paper's exponents and thresholds: colour difference exponent qc, the fraction pc of the
 * largest difference that is mapped to pt of the error range, feature width w (degrees), feature
 * exponent qf. */
static const float FLIP_QC = 0.7f;
static const float FLIP_PC = 0.4f;
static const float FLIP_PT = 0.95f;
static const float FLIP_W = 0.082f;
static const float FLIP_QF = 0.5f;

/* Contrast sensitivity of the three YCxCz channels, each a1*G(b1) + a2*G(b2) in the paper's
 * Gaussian form (b in squared degrees); only blue-yellow uses the second term. */
static const float CSF_A1[3] = {1.0f, 1.0f, 34.1f};
static const float CSF_B1[3] = {0.0047f, 0.0053f, 0.04f};
static const float CSF_A2[3] = {0.0f, 0.0f, 13.5f};
static const float CSF_B2[3] = {1.0e-5f, 1.0e-5f, 0.025f};

/* D65 white, and its reciprocal, as the tool writes them. */
static const float WHITE[3] = {0.950428545f, 1.000000000f, 1.088900371f};
static const float INV_WHITE[3] = {1.052156925f, 1.000000000f, 0.918357670f};

// >>colour conversions

static float clamp01(float v)
{
    /* The comparisons are the tool's Max then Min: NaN fails v > 0 and reads as 0. */
    float m = v > 0.0f ? v : 0.0f;
    return m > 1.0f ? 1.0f : m;
}

static void rgb_to_xyz(const float rgb[3], float xyz[3])
{
    const float a11 = 10135552.0f / 24577794.0f, a12 = 8788810.0f / 24577794.0f,
                a13 = 4435075.0f / 24577794.0f;
    const float a21 = 2613072.0f / 12288897.0f, a22 = 8788810.0f / 12288897.0f,
                a23 = 887015.0f / 12288897.0f;
    const float a31 = 1425312.0f / 73733382.0f, a32 = 8788810.0f / 73733382.0f,
                a33 = 70074185.0f / 73733382.0f;
    xyz[0] = a11 * rgb[0] + a12 * rgb[1] + a13 * rgb[2];
    xyz[1] = a21 * rgb[0] + a22 * rgb[1] + a23 * rgb[2];
    xyz[2] = a31 * rgb[0] + a32 * rgb[1] + a33 * rgb[2];
}

static void xyz_to_rgb(const float xyz[3], float rgb[3])
{
    rgb[0] = 3.241003275f * xyz[0] + -1.537398934f * xyz[1] + -0.498615861f * xyz[2];
    rgb[1] = -0.969224334f * xyz[0] + 1.875930071f * xyz[1] + 0.041554224f * xyz[2];
    rgb[2] = 0.055639423f * xyz[0] + -0.204011202f * xyz[1] + 1.057148933f * xyz[2];
}

/* YCxCz is CIELab without the cube root: linear in XYZ, so it can be filtered. */
static void xyz_to_ycxcz(const float xyz[3], float out[3])
{
    float x = xyz[0] * INV_WHITE[0], y = xyz[1] * INV_WHITE[1], z = xyz[2] * INV_WHITE[2];
    out[0] = 116.0f * y - 16.0f;
    out[1] = 500.0f * (x - y);
    out[2] = 200.0f * (y - z);
}

static void ycxcz_to_xyz(const float in[3], float xyz[3])
{
    const float y = (in[0] + 16.0f) / 116.0f;
    const float cx = in[1] / 500.0f;
    const float cz = in[2] / 200.0f;
    xyz[0] = (y + cx) * WHITE[0];
    xyz[1] = y * WHITE[1];
    xyz[2] = (y - cz) * WHITE[2];
}

static float lab_f(float t)
{
    const float delta = 6.0f / 29.0f;
    const float delta_sq = delta * delta;
    const float delta_cube = delta * delta_sq;
    const float factor = 1.0f / (3.0f * delta_sq);
    const float term = 4.0f / 29.0f;
    return t > delta_cube ? powf(t, 1.0f / 3.0f) : factor * t + term;
}

static void xyz_to_lab(const float xyz[3], float lab[3])
{
    float fx = lab_f(xyz[0] * INV_WHITE[0]);
    float fy = lab_f(xyz[1] * INV_WHITE[1]);
    float fz = lab_f(xyz[2] * INV_WHITE[2]);
    lab[0] = 116.0f * fy - 16.0f;
    lab[1] = 500.0f * (fx - fy);
    lab[2] = 200.0f * (fy - fz);
}

/* Hunt effect: chroma is less visible in the dark, so a and b are scaled by 0.01 L. */
static void lab_hunt(float lab[3])
{
    lab[1] = 0.01f * lab[0] * lab[1];
    lab[2] = 0.01f * lab[0] * lab[2];
}

/* HyAB: city-block in lightness plus Euclidean in chroma, better than Euclidean Lab for large
 * differences (the paper, section 4.1). */
static float hyab(const float p[3], const float q[3])
{
    float dl = fabsf(p[0] - q[0]);
    float dab = sqrtf((p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
    return dl + dab;
}

static void rgb_to_hunt_lab(const float rgb[3], float lab[3])
{
    float xyz[3];
    rgb_to_xyz(rgb, xyz);
    xyz_to_lab(xyz, lab);
    lab_hunt(lab);
}

/* cmax: the largest colour difference, taken as that between pure green and pure blue, raised to
 * qc. Errors are normalized against it. */
static float max_colour_distance(void)
{
    const float green[3] = {0.0f, 1.0f, 0.0f}, blue[3] = {0.0f, 0.0f, 1.0f};
    float g[3], b[3];
    rgb_to_hunt_lab(green, g);
    rgb_to_hunt_lab(blue, b);
    return powf(hyab(g, b), FLIP_QC);
}

// >>filters

/* The paper's Gaussian in its frequency-derived form, at squared distance x2 (degrees^2). */
static float csf_gaussian(float x2, float a, float b)
{
    const float pi = FLIP_PI, pi_sq = FLIP_PI * FLIP_PI;
    return a * sqrtf(pi / b) * expf(-pi_sq * x2 / b);
}

/* A 1D factor of csf_gaussian: its outer product with itself is the 2D Gaussian, weight a
 * included, which is what lets the blue-yellow sum of two Gaussians be run separably. */
static float csf_gaussian_sqrt(float x2, float a, float b)
{
    const float pi = FLIP_PI, pi_sq = FLIP_PI * FLIP_PI;
    return sqrtf(a * sqrtf(pi / b)) * expf(-pi_sq * x2 / b);
}

/* Three standard deviations of the widest CSF Gaussian, in pixels. */
static int spatial_radius(float ppd)
{
    const float pi_sq = FLIP_PI * FLIP_PI;
    float bmax = 0.0f;
    for (int c = 0; c < 3; c++) {
        bmax = CSF_B1[c] > bmax ? CSF_B1[c] : bmax;
        bmax = CSF_B2[c] > bmax ? CSF_B2[c] : bmax;
    }
    return (int)ceilf(3.0f * sqrtf(bmax / (2.0f * pi_sq)) * ppd);
}

/* 1D colour kernels, 2r+1 taps each: achromatic, red-green, and the two blue-yellow terms. */
typedef struct spatial_kernels {
    int radius;
    float *y, *cx, *cz1, *cz2;
} spatial_kernels;

static void spatial_kernels_fill(spatial_kernels *k, float ppd)
{
    const int r = k->radius, n = 2 * r + 1;
    const float dx = 1.0f / ppd;
    float sum_y = 0.0f, sum_cx = 0.0f, sum_cz1 = 0.0f, sum_cz2 = 0.0f;
    for (int i = 0; i < n; i++) {
        float x = (float)(i - r) * dx;
        float x2 = x * x;
        k->y[i] = csf_gaussian(x2, CSF_A1[0], CSF_B1[0]);
        k->cx[i] = csf_gaussian(x2, CSF_A1[1], CSF_B1[1]);
        k->cz1[i] = csf_gaussian_sqrt(x2, CSF_A1[2], CSF_B1[2]);
        k->cz2[i] = csf_gaussian_sqrt(x2, CSF_A2[2], CSF_B2[2]);
        sum_y += k->y[i];
        sum_cx += k->cx[i];
        sum_cz1 += k->cz1[i];
        sum_cz2 += k->cz2[i];
    }
    /* Unit DC gain in 2D. For blue-yellow the 2D sum is sum_cz1^2 + sum_cz2^2, so both 1D
     * factors are divided by its square root. */
    const float norm_y = 1.0f / sum_y, norm_cx = 1.0f / sum_cx;
    const float norm_cz = 1.0f / sqrtf(sum_cz1 * sum_cz1 + sum_cz2 * sum_cz2);
    for (int i = 0; i < n; i++) {
        k->y[i] *= norm_y;
        k->cx[i] *= norm_cx;
        k->cz1[i] *= norm_cz;
        k->cz2[i] *= norm_cz;
    }
}

/* Feature kernels: a Gaussian of standard deviation w/2 degrees and its 1st and 2nd
 * derivatives, 2r+1 taps, r = ceil(3 sigma). */
typedef struct feature_kernels {
    int radius;
    float sigma;
    float *g, *dg, *ddg;
} feature_kernels;

static float feature_sigma(float ppd)
{
    return 0.5f * FLIP_W * ppd;
}

static void feature_kernels_fill(feature_kernels *k)
{
    const int r = k->radius, n = 2 * r + 1;
    const float sd = k->sigma;
    float g_sum = 0.0f, dg_pos = 0.0f, dg_neg = 0.0f, ddg_pos = 0.0f, ddg_neg = 0.0f;
    for (int i = 0; i < n; i++) {
        const float x = (float)(i - r);
        const float g = expf(-(x * x) / (2.0f * sd * sd));
        const float dg = -x * g;
        const float ddg = (x * x / (sd * sd) - 1.0f) * g;
        g_sum += g;
        if (dg > 0.0f)
            dg_pos += dg;
        else
            dg_neg -= dg;
        if (ddg > 0.0f)
            ddg_pos += ddg;
        else
            ddg_neg -= ddg;
        k->g[i] = g;
        k->dg[i] = dg;
        k->ddg[i] = ddg;
    }
    /* The Gaussian sums to 1; the positive lobes of each derivative sum to 1 and the negative
     * ones to -1, so a unit step gives the same response at any ppd. */
    for (int i = 0; i < n; i++) {
        k->g[i] /= g_sum;
        k->dg[i] /= k->dg[i] > 0.0f ? dg_pos : dg_neg;
        k->ddg[i] /= k->ddg[i] > 0.0f ? ddg_pos : ddg_neg;
    }
}

static int clamp_index(int i, int n)
{
    return i < 0 ? 0 : i >= n ? n - 1 : i;
}

// >>pipelines

/* Work planes of one image, width*height floats each. */
typedef struct flip_planes {
    float *y, *cx, *cz;     /* YCxCz of the clamped input */
    float *t0, *t1, *t2, *t3; /* after the x pass: colour Y, Cx, Cz1, Cz2; then features */
} flip_planes;

static void to_ycxcz(const float *const rgb[3], size_t n, flip_planes *p)
{
    for (size_t i = 0; i < n; i++) {
        float c[3] = {clamp01(rgb[0][i]), clamp01(rgb[1][i]), clamp01(rgb[2][i])}, xyz[3], o[3];
        rgb_to_xyz(c, xyz);
        xyz_to_ycxcz(xyz, o);
        p->y[i] = o[0];
        p->cx[i] = o[1];
        p->cz[i] = o[2];
    }
}

/* x pass of the colour filters into t0..t3. */
static void colour_filter_x(const spatial_kernels *k, int w, int h, flip_planes *p)
{
    const int r = k->radius;
    for (int y = 0; y < h; y++) {
        const size_t row = (size_t)y * (size_t)w;
        for (int x = 0; x < w; x++) {
            float sy = 0.0f, scx = 0.0f, scz1 = 0.0f, scz2 = 0.0f;
            for (int i = -r; i <= r; i++) {
                const size_t s = row + (size_t)clamp_index(x + i, w);
                sy += k->y[i + r] * p->y[s];
                scx += k->cx[i + r] * p->cx[s];
                scz1 += k->cz1[i + r] * p->cz[s];
                scz2 += k->cz2[i + r] * p->cz[s];
            }
            p->t0[row + (size_t)x] = sy;
            p->t1[row + (size_t)x] = scx;
            p->t2[row + (size_t)x] = scz1;
            p->t3[row + (size_t)x] = scz2;
        }
    }
}

/* y pass of the colour filters at (x, y), then the filtered colour as Hunt-adjusted CIELab. The
 * filtered colour can leave the RGB gamut; it is clamped there, as the paper does. */
static void colour_filter_y_lab(const spatial_kernels *k, int w, int h, const flip_planes *p,
                                int x, int y, float lab[3])
{
    const int r = k->radius;
    float sy = 0.0f, scx = 0.0f, scz1 = 0.0f, scz2 = 0.0f;
    for (int i = -r; i <= r; i++) {
        const size_t s = (size_t)clamp_index(y + i, h) * (size_t)w + (size_t)x;
        sy += k->y[i + r] * p->t0[s];
        scx += k->cx[i + r] * p->t1[s];
        scz1 += k->cz1[i + r] * p->t2[s];
        scz2 += k->cz2[i + r] * p->t3[s];
    }
    const float ycc[3] = {sy, scx, scz1 + scz2};
    float xyz[3], rgb[3];
    ycxcz_to_xyz(ycc, xyz);
    xyz_to_rgb(xyz, rgb);
    for (int c = 0; c < 3; c++)
        rgb[c] = clamp01(rgb[c]);
    rgb_to_hunt_lab(rgb, lab);
}

/* Colour error of every pixel into err: HyAB^qc, remapped so that [0, pc*cmax) covers [0, pt)
 * and [pc*cmax, cmax] the rest, compressing the large differences. */
static void colour_error(const spatial_kernels *k, int w, int h, const flip_planes *ref,
                         const flip_planes *test, float *err)
{
    const float cmax = max_colour_distance();
    const float pccmax = FLIP_PC * cmax;
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            float lr[3], lt[3];
            colour_filter_y_lab(k, w, h, ref, x, y, lr);
            colour_filter_y_lab(k, w, h, test, x, y, lt);
            float d = powf(hyab(lr, lt), FLIP_QC);
            if (d < pccmax)
                d *= FLIP_PT / pccmax;
            else
                d = FLIP_PT + ((d - pccmax) / (cmax - pccmax)) * (1.0f - FLIP_PT);
            err[(size_t)y * (size_t)w + (size_t)x] = d;
        }
    }
}

/* x pass of the feature filters on the achromatic channel, normalized to [0, 1]: d/dx into t0,
 * d2/dx2 into t1, the Gaussian into t2 (for the y derivatives). */
static void feature_filter_x(const feature_kernels *k, int w, int h, flip_planes *p)
{
    const int r = k->radius;
    const float one_over_116 = 1.0f / 116.0f, sixteen_over_116 = 16.0f / 116.0f;
    for (int y = 0; y < h; y++) {
        const size_t row = (size_t)y * (size_t)w;
        for (int x = 0; x < w; x++) {
            float d = 0.0f, dd = 0.0f, g = 0.0f;
            for (int i = -r; i <= r; i++) {
                const float v = p->y[row + (size_t)clamp_index(x + i, w)] * one_over_116 +
                                sixteen_over_116;
                d += k->dg[i + r] * v;
                dd += k->ddg[i + r] * v;
                g += k->g[i + r] * v;
            }
            p->t0[row + (size_t)x] = d;
            p->t1[row + (size_t)x] = dd;
            p->t2[row + (size_t)x] = g;
        }
    }
}

/* y pass at (x, y): edge strength |grad| and point strength |(d2/dx2, d2/dy2)|. */
static void feature_filter_y(const feature_kernels *k, int w, int h, const flip_planes *p, int x,
                             int y, float *edge, float *point)
{
    const int r = k->radius;
    float dx = 0.0f, ddx = 0.0f, dy = 0.0f, ddy = 0.0f;
    for (int i = -r; i <= r; i++) {
        const size_t s = (size_t)clamp_index(y + i, h) * (size_t)w + (size_t)x;
        dx += k->g[i + r] * p->t0[s];
        ddx += k->g[i + r] * p->t1[s];
        dy += k->dg[i + r] * p->t2[s];
        ddy += k->ddg[i + r] * p->t2[s];
    }
    *edge = sqrtf(dx * dx + dy * dy);
    *point = sqrtf(ddx * ddx + ddy * ddy);
}

/* Feature difference of every pixel, and the final error err = colour ^ (1 - feature): a feature
 * difference pushes the colour error towards 1. */
static void feature_error_combine(const feature_kernels *k, int w, int h, const flip_planes *ref,
                                  const flip_planes *test, float *err)
{
    const float norm = 1.0f / sqrtf(2.0f);
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            float er, pr, et, pt;
            feature_filter_y(k, w, h, ref, x, y, &er, &pr);
            feature_filter_y(k, w, h, test, x, y, &et, &pt);
            const float de = fabsf(er - et), dp = fabsf(pr - pt);
            const float f = powf(norm * (de > dp ? de : dp), FLIP_QF);
            const size_t i = (size_t)y * (size_t)w + (size_t)x;
            err[i] = powf(err[i], 1.0f - f);
        }
    }
}

// >>entry points

fs_status flip_ldr(const float *const ref[3], const float *const test[3], int width, int height,
                   double ppd_in, float *err)
{
    if (!ref || !test || !err || !ref[0] || !ref[1] || !ref[2] || !test[0] || !test[1] ||
        !test[2])
        return FS_ERR_USAGE;
    if (width <= 0 || height <= 0 || !(ppd_in > 0.0 && ppd_in <= FLIP_MAX_PPD))
        return FS_ERR_USAGE;
    const size_t n = (size_t)width * (size_t)height;
    const float ppd = (float)ppd_in;

    spatial_kernels sk = {.radius = spatial_radius(ppd)};
    feature_kernels fk = {.sigma = feature_sigma(ppd)};
    fk.radius = (int)ceilf(3.0f * fk.sigma);
    const size_t sn = (size_t)(2 * sk.radius + 1), fn = (size_t)(2 * fk.radius + 1);

    /* 14 planes (7 per image) and the kernels, in one block. */
    const size_t planes = 14;
    if (n > (SIZE_MAX / sizeof(float) - 4 * sn - 3 * fn) / planes)
        return FS_ERR_USAGE;
    float *mem = malloc((planes * n + 4 * sn + 3 * fn) * sizeof *mem);
    if (!mem)
        return FS_ERR_NOMEM;
    float *q = mem;
    flip_planes pr, pt;
    flip_planes *all[2] = {&pr, &pt};
    for (int j = 0; j < 2; j++) {
        float **f[7] = {&all[j]->y,  &all[j]->cx, &all[j]->cz, &all[j]->t0,
                        &all[j]->t1, &all[j]->t2, &all[j]->t3};
        for (int m = 0; m < 7; m++, q += n)
            *f[m] = q;
    }
    sk.y = q, q += sn;
    sk.cx = q, q += sn;
    sk.cz1 = q, q += sn;
    sk.cz2 = q, q += sn;
    fk.g = q, q += fn;
    fk.dg = q, q += fn;
    fk.ddg = q;

    spatial_kernels_fill(&sk, ppd);
    feature_kernels_fill(&fk);
    to_ycxcz(ref, n, &pr);
    to_ycxcz(test, n, &pt);

    colour_filter_x(&sk, width, height, &pr);
    colour_filter_x(&sk, width, height, &pt);
    colour_error(&sk, width, height, &pr, &pt, err);

    /* The x-pass planes are free again: reuse them for the feature pass. */
    feature_filter_x(&fk, width, height, &pr);
    feature_filter_x(&fk, width, height, &pt);
    feature_error_combine(&fk, width, height, &pr, &pt, err);

    free(mem);
    return FS_OK;
}

double flip_ppd(double distance_m, double resolution_x, double monitor_width_m)
{
    const float dist = (float)distance_m, res = (float)resolution_x, mw = (float)monitor_width_m;
    return (double)(dist * (res / mw) * (FLIP_PI / 180.0f));
}

double flip_mean(const float *err, int width, int height)
{
    if (!err || width <= 0 || height <= 0)
        return 0.0;
    const size_t n = (size_t)width * (size_t)height;
    double s = 0.0;
    for (size_t i = 0; i < n; i++)
        s += (double)err[i];
    return s / (double)n;
}

float flip_srgb_to_linear(unsigned char code)
{
    const float s = (float)code / 255.0f;
    if (s <= 0.04045f)
        return s / 12.92f;
    return powf((s + 0.055f) / 1.055f, 2.4f);
}
