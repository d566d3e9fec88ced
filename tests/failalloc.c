/* See failalloc.h. */
#include <stdlib.h>
#include "failalloc.h"
#include "ntile/ntile.h"

static long g_live, g_budget;

static void *counting_alloc(size_t size, void *user)
{
    (void)user;
    if (g_budget == 0) return NULL;
    if (g_budget > 0) g_budget--;
    void *p = malloc(size);
    if (p) g_live++;
    return p;
}

static void counting_free(void *p, void *user)
{
    (void)user;
    g_live--;
    free(p);
}

void failalloc_begin(long budget)
{
    g_live = 0;
    g_budget = budget;
    nt_set_allocator(counting_alloc, counting_free, NULL);
}

long failalloc_end(void)
{
    nt_set_allocator(NULL, NULL, NULL);
    return g_live;
}
