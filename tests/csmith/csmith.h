/* A freestanding replacement for csmith's runtime header (csmith.h): the CRC-32 the
 * generated programs hash their globals with, and `checksum = %X` printed without libc.
 * Built two ways by tests/csmith.rs: by trax (clang-14 for TRaX, output through
 * trax_print_char) and for i386 Linux as a static program without libc (output through
 * the write system call), an ILP32 oracle with csmith's own safe_math.h on both sides. */
#ifndef TRAX_CSMITH_H
#define TRAX_CSMITH_H

#include <stdint.h>
#include <limits.h>
#include <float.h>

#ifdef __mips__
#include <trax.h>
static void out_char(char c) { trax_print_char((unsigned char)c); }
#else
static void out_char(char c) {
    int ret;
    __asm__ volatile("int $0x80" : "=a"(ret) : "a"(4), "b"(1), "c"(&c), "d"(1) : "memory");
    (void)ret;
}
#endif

static void out_str(const char *s) {
    while (*s) out_char(*s++);
}

static void out_hex(uint32_t v) {
    int started = 0;
    for (int i = 7; i >= 0; i--) {
        unsigned d = (v >> (4 * i)) & 15u;
        if (d || started || i == 0) {
            out_char((char)(d < 10 ? '0' + d : 'A' + d - 10));
            started = 1;
        }
    }
}

/* C's strict aliasing rule makes it undefined to reach one object through lvalues of two
 * integer types, and csmith's programs do (seed 5627: `uint16_t *g_160` and
 * `int32_t *g_304` point into the same union): their checksums then depend on the
 * optimiser (i386 and MIPS alike print another checksum at -O1 than at -O0/2/3). Every
 * integer type the programs use gets `may_alias` (a per-type -fno-strict-aliasing), on
 * both sides, so the programs are defined and the checksum is one at every level. */
#define CSMITH_MAY_ALIAS(t) typedef t __attribute__((may_alias)) csmith_##t;
CSMITH_MAY_ALIAS(int8_t)
CSMITH_MAY_ALIAS(uint8_t)
CSMITH_MAY_ALIAS(int16_t)
CSMITH_MAY_ALIAS(uint16_t)
CSMITH_MAY_ALIAS(int32_t)
CSMITH_MAY_ALIAS(uint32_t)
CSMITH_MAY_ALIAS(int64_t)
CSMITH_MAY_ALIAS(uint64_t)
#undef CSMITH_MAY_ALIAS
#define int8_t csmith_int8_t
#define uint8_t csmith_uint8_t
#define int16_t csmith_int16_t
#define uint16_t csmith_uint16_t
#define int32_t csmith_int32_t
#define uint32_t csmith_uint32_t
#define int64_t csmith_int64_t
#define uint64_t csmith_uint64_t

/* Only csmith's `printf`s with no arguments (print_hash_value is 0) reach here. */
#define printf(...) ((void)0)

/* What csmith's random_inc.h defines around safe_math.h (csmith's own file). */
#define STATIC static
#define UNDEFINED(__val) (__val)
#define LOG_INDEX
#define LOG_EXEC
#define FUNC_NAME(x) (safe_##x)
#include "safe_math.h"
#undef FUNC_NAME
#define INT_BIT (sizeof(int) * CHAR_BIT)
#define _CSMITH_BITFIELD(x) (((x) > INT_BIT) ? ((x) % INT_BIT) : (x))

static uint32_t crc32_tab[256];
static uint32_t crc32_context = 0xFFFFFFFFUL;

static void crc32_gentab(void) {
    const uint32_t poly = 0xEDB88320UL;
    for (int i = 0; i < 256; i++) {
        uint32_t crc = (uint32_t)i;
        for (int j = 8; j > 0; j--)
            crc = (crc & 1) ? (crc >> 1) ^ poly : crc >> 1;
        crc32_tab[i] = crc;
    }
}

static void crc32_byte(uint8_t b) {
    crc32_context = ((crc32_context >> 8) & 0x00FFFFFF) ^ crc32_tab[(crc32_context ^ b) & 0xFF];
}

static void crc32_8bytes(uint64_t val) {
    for (int i = 0; i < 8; i++) crc32_byte((uint8_t)(val >> (8 * i)));
}

static void transparent_crc(uint64_t val, char *vname, int flag) {
    (void)vname;
    (void)flag;
    crc32_8bytes(val);
}

static void transparent_crc_bytes(char *ptr, int nbytes, char *vname, int flag) {
    (void)vname;
    (void)flag;
    for (int i = 0; i < nbytes; i++) crc32_byte((uint8_t)ptr[i]);
}

static void platform_main_begin(void) {}

static void platform_main_end(uint32_t crc, int flag) {
    (void)flag;
    out_str("checksum = ");
    out_hex(crc);
    out_char('\n');
}

#endif
