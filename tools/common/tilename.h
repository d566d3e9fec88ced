/* N tile names typed by people: a case-insensitive lookup and the closest name for a
 * "did you mean" hint. Shared by `ntile query` and the Tiled importer. Header only,
 * so that each program keeps its own link line. */
#ifndef NTILE_TOOLS_TILENAME_H
#define NTILE_TOOLS_TILENAME_H

#include <ctype.h>
#include <string.h>
#include "ntile/tiles.h"

/* The tile whose N name equals s ignoring case (the names differ in more than case:
 * "45DEGpn" and "45DEGnp" differ in letter order), or -1. */
static inline int tilename_lookup(const char *s)
{
    for (int i = 0; i < NT_TILE_COUNT; i++) {
        const char *n = nt_tile_get_info(i)->name;
        size_t k = 0;
        while (n[k] && s[k] && tolower((unsigned char)n[k]) == tolower((unsigned char)s[k])) k++;
        if (!n[k] && !s[k]) return i;
    }
    return -1;
}

/* Edit distance (insertions, deletions, substitutions, swaps of neighbours) between a
 * and b ignoring case, counted up to `limit` + 1 (longer words give limit + 1). */
static inline int tilename_distance(const char *a, const char *b, int limit)
{
    enum { MAXW = 32 };
    size_t la = strlen(a), lb = strlen(b);
    if (la >= MAXW || lb >= MAXW) return limit + 1;
    int d[MAXW + 1][MAXW + 1];
    for (size_t i = 0; i <= la; i++) d[i][0] = (int)i;
    for (size_t j = 0; j <= lb; j++) d[0][j] = (int)j;
    for (size_t i = 1; i <= la; i++) {
        for (size_t j = 1; j <= lb; j++) {
            int ca = tolower((unsigned char)a[i - 1]), cb = tolower((unsigned char)b[j - 1]);
            int v = d[i - 1][j - 1] + (ca != cb);
            if (d[i - 1][j] + 1 < v) v = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < v) v = d[i][j - 1] + 1;
            if (i > 1 && j > 1 && ca == tolower((unsigned char)b[j - 2]) && tolower((unsigned char)a[i - 2]) == cb &&
                d[i - 2][j - 2] + 1 < v)
                v = d[i - 2][j - 2] + 1;
            d[i][j] = v;
        }
    }
    return d[la][lb] > limit ? limit + 1 : d[la][lb];
}

/* The N tile name closest to s (at most 2 edits, or a third of its length when
 * longer), for "did you mean"; NULL when no name is that close or two are equally
 * close. */
static inline const char *tilename_suggest(const char *s)
{
    int limit = (int)strlen(s) / 3 > 2 ? (int)strlen(s) / 3 : 2;
    int best = limit + 1, ties = 0;
    const char *name = NULL;
    for (int i = 0; i < NT_TILE_COUNT; i++) {
        const char *n = nt_tile_get_info(i)->name;
        int dist = tilename_distance(s, n, limit);
        if (dist < best) {
            best = dist;
            name = n;
            ties = 0;
        } else if (dist == best) {
            ties++;
        }
    }
    return best <= limit && ties == 0 ? name : NULL;
}

#endif
