/* ntile bench — Pareto fronts, CSV splitting and SVG plots (see plot.h). */
#include "plot.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

int plot_pareto(plot_point *p, int n)
{
    int count = 0;
    for (int i = 0; i < n; i++) {
        int beaten = 0;
        for (int j = 0; j < n && !beaten; j++)
            beaten = j != i && p[j].x <= p[i].x && p[j].y <= p[i].y && (p[j].x < p[i].x || p[j].y < p[i].y);
        p[i].front = !beaten;
        count += !beaten;
    }
    return count;
}

int csv_split(char *line, char **fields, int max)
{
    int n = 0;
    char *s = line;
    size_t len = strlen(s);
    while (len > 0 && (s[len - 1] == '\n' || s[len - 1] == '\r')) s[--len] = 0;
    for (;;) {
        if (n < max) fields[n] = s;
        n++;
        char *c = strchr(s, ',');
        if (!c) break;
        *c = 0;
        s = c + 1;
    }
    return n < max ? n : max;
}

static const char *const colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
#define NCOLOURS (int)(sizeof colours / sizeof colours[0])

enum { PANEL_W = 520, PANEL_H = 400, MARGIN_L = 70, MARGIN_R = 20, MARGIN_T = 40, MARGIN_B = 60 };

/* Text for SVG: the characters that need escaping. */
static void put_text(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '<') fputs("&lt;", f);
        else if (*s == '>') fputs("&gt;", f);
        else if (*s == '&') fputs("&amp;", f);
        else fputc(*s, f);
    }
}

static void panel_svg(FILE *f, const plot_panel *pn, double ox, const char *const *series, int nseries)
{
    double lx0 = 1e300, lx1 = -1e300, ly0 = 1e300, ly1 = -1e300;
    for (int i = 0; i < pn->count; i++) {
        double lx = log10(pn->points[i].x), ly = log10(pn->points[i].y);
        lx0 = fmin(lx0, lx), lx1 = fmax(lx1, lx), ly0 = fmin(ly0, ly), ly1 = fmax(ly1, ly);
    }
    if (pn->count == 0) lx0 = ly0 = 0, lx1 = ly1 = 1;
    lx0 = floor(lx0), ly0 = floor(ly0), lx1 = ceil(lx1), ly1 = ceil(ly1);
    if (lx1 <= lx0) lx1 = lx0 + 1;
    if (ly1 <= ly0) ly1 = ly0 + 1;
    double w = PANEL_W - MARGIN_L - MARGIN_R, h = PANEL_H - MARGIN_T - MARGIN_B;
#define PX(lx) (ox + MARGIN_L + ((lx) - lx0) / (lx1 - lx0) * w)
#define PY(ly) (MARGIN_T + h - ((ly) - ly0) / (ly1 - ly0) * h)
    fprintf(f, "<g>\n<text x=\"%.1f\" y=\"22\" font-size=\"15\" text-anchor=\"middle\">", ox + MARGIN_L + w / 2);
    put_text(f, pn->title);
    fprintf(f, "</text>\n<rect x=\"%.1f\" y=\"%d\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"#000\"/>\n",
            ox + MARGIN_L, MARGIN_T, w, h);
    for (double d = lx0; d <= lx1 + 1e-9; d++)
        fprintf(f,
                "<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%.1f\" "
                "font-size=\"11\" text-anchor=\"middle\">1e%g</text>\n",
                PX(d), MARGIN_T, PX(d), MARGIN_T + h, PX(d), MARGIN_T + h + 16, d);
    /* minor ticks at 2..9 x 10^d, labelled at 2 and 5 when an axis spans few decades */
    for (double d = lx0; d < lx1; d++)
        for (int m = 2; m < 10; m++) {
            double lx = d + log10(m);
            fprintf(f, "<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#f0f0f0\"/>\n", PX(lx), MARGIN_T,
                    PX(lx), MARGIN_T + h);
            if ((m == 2 || m == 5) && lx1 - lx0 <= 2)
                fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"10\" text-anchor=\"middle\">%g</text>\n", PX(lx),
                        MARGIN_T + h + 16, m * pow(10, d));
        }
    for (double d = ly0; d <= ly1 + 1e-9; d++)
        fprintf(f,
                "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%.1f\" "
                "font-size=\"11\" text-anchor=\"end\">1e%g</text>\n",
                ox + MARGIN_L, PY(d), ox + MARGIN_L + w, PY(d), ox + MARGIN_L - 4, PY(d) + 4, d);
    fprintf(f, "<text x=\"%.1f\" y=\"%d\" font-size=\"12\" text-anchor=\"middle\">", ox + MARGIN_L + w / 2,
            PANEL_H - 20);
    put_text(f, pn->xlabel);
    fprintf(f, "</text>\n<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\" text-anchor=\"middle\" "
               "transform=\"rotate(-90 %.1f %.1f)\">",
            ox + 16, MARGIN_T + h / 2, ox + 16, MARGIN_T + h / 2);
    put_text(f, pn->ylabel);
    fputs("</text>\n", f);
    /* the front, in x order */
    int *idx = malloc(sizeof *idx * (size_t)(pn->count > 0 ? pn->count : 1)), nf = 0;
    if (idx) {
        for (int i = 0; i < pn->count; i++)
            if (pn->points[i].front) idx[nf++] = i;
        for (int a = 1; a < nf; a++)
            for (int b = a; b > 0 && pn->points[idx[b]].x < pn->points[idx[b - 1]].x; b--) {
                int t = idx[b];
                idx[b] = idx[b - 1];
                idx[b - 1] = t;
            }
        if (nf > 1) {
            fputs("<polyline fill=\"none\" stroke=\"#444\" stroke-dasharray=\"4 3\" points=\"", f);
            for (int k = 0; k < nf; k++)
                fprintf(f, "%s%.1f,%.1f", k ? " " : "", PX(log10(pn->points[idx[k]].x)), PY(log10(pn->points[idx[k]].y)));
            fputs("\"/>\n", f);
        }
        free(idx);
    }
    for (int i = 0; i < pn->count; i++) {
        const plot_point *p = &pn->points[i];
        const char *c = colours[(p->series % NCOLOURS + NCOLOURS) % NCOLOURS];
        fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" stroke=\"%s\" fill=\"%s\"><title>", PX(log10(p->x)),
                PY(log10(p->y)), c, p->front ? c : "none");
        put_text(f, p->label);
        fprintf(f, ": %.4g, %.3g</title></circle>\n", p->x, p->y);
        if (p->front) { /* name the points of the front */
            int right = PX(log10(p->x)) > ox + MARGIN_L + w / 2; /* keep the text inside the panel */
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"9\" fill=\"%s\" text-anchor=\"%s\">",
                    PX(log10(p->x)) + (right ? -6 : 6), PY(log10(p->y)) - 5, c, right ? "end" : "start");
            put_text(f, p->label);
            fputs("</text>\n", f);
        }
    }
    for (int s = 0; s < nseries; s++) {
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" fill=\"%s\">", ox + MARGIN_L + 8,
                (double)MARGIN_T + 14 + 14 * s, colours[s % NCOLOURS]);
        put_text(f, series[s]);
        fputs("</text>\n", f);
    }
    fputs("</g>\n", f);
#undef PX
#undef PY
}

int plot_svg(FILE *f, const plot_panel *panels, int npanels, const char *const *series, int nseries)
{
    fprintf(f,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" "
            "height=\"%d\" font-family=\"sans-serif\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"#fff\"/>\n",
            PANEL_W * npanels, PANEL_H);
    for (int k = 0; k < npanels; k++) panel_svg(f, &panels[k], (double)PANEL_W * k, series, nseries);
    fputs("</svg>\n", f);
    return !ferror(f);
}
