/* tools/common/tool.h - what every command-line tool shares: program name,
 * error lines, a terminal progress bar, number formatting.
 * Only tools print and exit; the libraries report through vx_error. */
#ifndef VX_TOOL_H
#define VX_TOOL_H

#include <stdbool.h>
#include <stdint.h>

#include "svo/core.h"

/* Basename of argv[0], set by vx_tool_init (at the start of main, before any
 * thread: then only read). */
extern const char* vx_tool_name;
void vx_tool_init(int argc, char** argv);

/* "tool: file: message" on stderr; returns 1 (the tools' failure status). */
int vx_tool_error(const char* file, const vx_error* err);
/* Whether msg starts with "file:" (the library's file functions name the
 * file in their I/O errors): a tool then prints msg without the name again. */
bool vx_tool_names_file(const char* file, const char* msg);
int vx_tool_errorf(const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

/* A usage mistake: "tool: <message>" on stderr, then usage(2), which must
 * print the help to stderr and exit with status 2. */
_Noreturn void vx_tool_usage_error(void (*usage)(int status), const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* The argument of the option argv[*i] (the option loops' one rule for it): argv[*i + 1], *i advanced to it;
 * where none is left, the usage error "option X needs an argument" (vx_tool_usage_error, which does not
 * return). So an error about the value can name it as argv[*i] afterwards. */
const char* vx_tool_arg(int argc, char** argv, int* i, void (*usage)(int status));

/* Progress bar on stderr when it is a terminal (quiet disables it). */
vx_progress vx_tool_progress(bool quiet);
void vx_tool_progress_done(void);

/* 1234567 -> "1,234,567" in a rotating buffer (4 slots per thread: valid
 * until the same thread's fourth next call). */
const char* vx_tool_num(uint64_t v);
/* bytes -> "12.3 MiB" (the same buffers' rules) */
const char* vx_tool_bytes(uint64_t v);

/* Parses a whole decimal number / a double; false if malformed. */
bool vx_tool_parse_u32(const char* s, uint32_t* out);
bool vx_tool_parse_double(const char* s, double* out);

/* Parses a byte count: a whole number with an optional K, M, G or T suffix
 * (powers of 1024; "512M", "2G"); false if malformed or above 2^62. */
bool vx_tool_parse_bytes(const char* s, uint64_t* out);
/* vx_tool_error, or, when the budget refused an allocation, a line naming
 * the cap: "tool: file: needs more than --max-memory 512.0 MiB (a block of 2.0 MiB
 * refused): msg". */
int vx_tool_error_budget(const char* file, const vx_error* err, const vx_budget* b);

/* Parses n comma-separated finite numbers ("1,2.5,-3"); false if malformed. */
bool vx_tool_parse_vec(const char* s, double* v, int n);

/* Logger printing warnings as "tool: warning: msg" (verbose also INFO). */
vx_logger vx_tool_logger(bool verbose);

/* Lower-case extension of path without the dot ("" if none), in a buffer of
 * the calling thread's (valid until its next call). */
const char* vx_tool_ext(const char* path);

/* The gi methods of the tools' pass pipelines (svo_render --passes, svo_view's passes): the names
 * gi=NAME takes, for one error that lists them all, and whether a method reads light field probes
 * (--probes FILE). probes/ gives probes, lightfield and pathtrace, photons/ and cones/ the other two. */
#define VX_TOOL_GI_METHODS "probes, lightfield, pathtrace, photons, cones"
bool vx_tool_gi_method_known(const char* name);
bool vx_tool_gi_method_needs_probes(const char* name);

#endif
