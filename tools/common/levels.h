/* Finding a shipped level by name, for the ntile CLI and the playground: a level
 * argument that is not an existing file and names no directory ("ninja",
 * "ninja.ntl") is looked up in the levels `make install` puts in
 * PREFIX/share/ntile/levels, found from the program's own place (PREFIX/bin, so an
 * installed tree can move). Linux (/proc/self/exe); elsewhere the name stays as given.
 * Header only, like stream.h. Needs _POSIX_C_SOURCE >= 200112L (readlink). */
#ifndef NTILE_TOOLS_LEVELS_H
#define NTILE_TOOLS_LEVELS_H

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The installed levels, relative to the directory of the program. */
#define LEVELS_INSTALLED "/../share/ntile/levels"

/* out = the directory of the installed levels (existing or not); 0 when the program's
 * own path is unknown or too long. */
static inline int levels_installed_dir(char *out, size_t cap)
{
    char exe[4096];
    ssize_t k = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (k <= 0) return 0;
    exe[k] = '\0';
    char *slash = strrchr(exe, '/');
    if (!slash) return 0;
    *slash = '\0';
    int n = snprintf(out, cap, "%s%s", exe, LEVELS_INSTALLED);
    return n > 0 && (size_t)n < cap;
}

static inline int levels_is_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* The level `name` names: name itself when it exists or holds a '/', else the
 * installed level NAME or NAME.ntl when there is one (written to out), else name (so
 * that the caller's message names what was asked for). */
static inline const char *levels_find(const char *name, char *out, size_t cap)
{
    char dir[4096];
    struct stat st;
    if (stat(name, &st) == 0 || strchr(name, '/') || !levels_installed_dir(dir, sizeof dir)) return name;
    static const char *const ext[2] = {"", ".ntl"};
    for (int i = 0; i < 2; i++) {
        int n = snprintf(out, cap, "%s/%s%s", dir, name, ext[i]);
        if (n > 0 && (size_t)n < cap && levels_is_file(out)) return out;
    }
    return name;
}

#endif
