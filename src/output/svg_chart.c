/* svg_chart.c: see svg_chart.h. */
#include "output/svg_chart.h"

#include <math.h>
#include <string.h>

void html_escape(sbuf *b, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '&': sb_puts(b, "&amp;"); break;
        case '<': sb_puts(b, "&lt;"); break;
        case '>': sb_puts(b, "&gt;"); break;
        case '"': sb_puts(b, "&quot;"); break;
        case '\'': sb_puts(b, "&#39;"); break;
        default: sb_append(b, s, 1);
        }
    }
}

/* A tick step of about a fifth of `span`: 1, 2 or 5 times a power of ten. */
static double tick_step(double span)
{
    double raw = span / 5.0, p = pow(10.0, floor(log10(raw))), f = raw / p;
    return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * p;
}

void svg_chart(sbuf *b, const svg_chart_desc *d)
{
    int w = d->width ? d->width : 640, h = d->height ? d->height : 300;
    const double ml = 70, mr = 150, mt = 28, mb = 46; /* margins: axis labels left and below, legend right */
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int s = 0; s < d->count; s++)
        for (int i = 0; i < d->series[s].n; i++) {
            double x = d->series[s].x[i], y = d->series[s].y[i];
            if (!isfinite(x) || !isfinite(y))
                continue;
            x0 = fmin(x0, x), x1 = fmax(x1, x), y0 = fmin(y0, y), y1 = fmax(y1, y);
        }
    if (!(x0 <= x1))
        x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    if (x1 - x0 < 1e-12)
        x0 -= 0.5, x1 += 0.5;
    if (y1 - y0 < 1e-12)
        y0 -= fmax(fabs(y0) * 0.1, 0.5), y1 += fmax(fabs(y1) * 0.1, 0.5);
    double pad = (y1 - y0) * 0.05;
    y0 -= pad, y1 += pad;
    double pw = w - ml - mr, ph = h - mt - mb;
#define PX(x) (ml + ((x) - x0) / (x1 - x0) * pw)
#define PY(y) (mt + (1.0 - ((y) - y0) / (y1 - y0)) * ph)
    sb_printf(b, "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"chart\" width=\"%d\" height=\"%d\" "
                 "viewBox=\"0 0 %d %d\"", w, h, w, h);
    if (d->id) {
        sb_puts(b, " id=\"");
        html_escape(b, d->id);
        sb_puts(b, "\"");
    }
    sb_puts(b, " font-family=\"sans-serif\" font-size=\"11\">\n<text x=\"");
    sb_printf(b, "%.1f\" y=\"16\" font-size=\"13\" font-weight=\"bold\">", ml);
    html_escape(b, d->title ? d->title : "");
    sb_printf(b, "</text>\n<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"#888\"/>\n",
              ml, mt, pw, ph);
    double sx = tick_step(x1 - x0), sy = tick_step(y1 - y0);
    if (d->x_whole && sx < 1.0)
        sx = 1.0;
    for (double t = ceil(x0 / sx) * sx; t <= x1 + sx * 1e-9; t += sx)
        sb_printf(b, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%.1f\" "
                     "text-anchor=\"middle\">%.6g</text>\n", PX(t), mt, PX(t), mt + ph, PX(t), mt + ph + 14,
                  fabs(t) < sx * 1e-9 ? 0.0 : t);
    for (double t = ceil(y0 / sy) * sy; t <= y1 + sy * 1e-9; t += sy)
        sb_printf(b, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%.1f\" "
                     "text-anchor=\"end\">%.6g</text>\n", ml, PY(t), ml + pw, PY(t), ml - 4, PY(t) + 4,
                  fabs(t) < sy * 1e-9 ? 0.0 : t);
    sb_printf(b, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">", ml + pw / 2, h - 8);
    html_escape(b, d->xlabel ? d->xlabel : "");
    sb_printf(b, "</text>\n<text transform=\"translate(14,%.1f) rotate(-90)\" text-anchor=\"middle\">", mt + ph / 2);
    html_escape(b, d->ylabel ? d->ylabel : "");
    sb_puts(b, "</text>\n");
    for (int s = 0; s < d->count; s++) {
        const svg_series *se = &d->series[s];
        if (se->line) {
            bool open = false;
            for (int i = 0; i < se->n; i++) {
                bool ok = isfinite(se->x[i]) && isfinite(se->y[i]);
                if (ok && !open) {
                    sb_puts(b, "<polyline fill=\"none\" stroke-width=\"1.5\" stroke=\"");
                    html_escape(b, se->colour);
                    sb_puts(b, "\" points=\"");
                    open = true;
                }
                if (ok)
                    sb_printf(b, "%.1f,%.1f ", PX(se->x[i]), PY(se->y[i]));
                if (open && (!ok || i + 1 == se->n)) {
                    sb_puts(b, "\"/>\n");
                    open = false;
                }
            }
        }
        if (se->points)
            for (int i = 0; i < se->n; i++)
                if (isfinite(se->x[i]) && isfinite(se->y[i])) {
                    sb_printf(b, "<circle r=\"3.5\" cx=\"%.1f\" cy=\"%.1f\" fill=\"", PX(se->x[i]), PY(se->y[i]));
                    html_escape(b, se->colour);
                    sb_puts(b, "\"/>\n");
                }
        double ly = mt + 10 + 16 * s;
        sb_printf(b, "<rect x=\"%.1f\" y=\"%.1f\" width=\"12\" height=\"4\" fill=\"", ml + pw + 10, ly - 4);
        html_escape(b, se->colour);
        sb_printf(b, "\"/><text x=\"%.1f\" y=\"%.1f\">", ml + pw + 26, ly + 2);
        html_escape(b, se->name ? se->name : "");
        sb_puts(b, "</text>\n");
    }
    sb_puts(b, "</svg>\n");
#undef PX
#undef PY
}
