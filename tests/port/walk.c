/*
 * Walks a generated port object dictionary the way the library addresses it and prints,
 * for every index, one line "IIII n=N" and for every subindex one line
 *   IIII SS t=TYPE a=ATTR d=DEFAULT v=DATA
 * DEFAULT comes from pDefaultVal (numbers in decimal, REAL32 as its bit pattern, strings
 * and domains as their STRING_DATA_T / DOMAIN_DATA_T lengths); DATA is the value in the
 * object's data at the subindex's address (byte-packed layout), strings and domains in hex.
 * Built with CONFIG_LIMITS_CHECK and WALK_LIMITS, a subindex with pLimits also prints
 * " l=LOW..HIGH" (numbers as DEFAULT).
 * tests/test_export_port.py compares this output with the model.
 */
#include <stdio.h>
#include <string.h>
#include "co_acces.h"

#ifndef OD_SYMBOL
#  define OD_SYMBOL objDir
#endif
#define CAT2(a, b) a##b
#define CAT(a, b) CAT2(a, b)

extern LIST_ELEMENT_T OD_SYMBOL[];
extern const UNSIGNED16 CAT(OD_SYMBOL, Elements);

static const VALUE_DESC_T *desc_of(const LIST_ELEMENT_T *o, unsigned sub)
{
    if (sub != 0u && (o->pValDesc[0].attribute & CO_SHORT_ARRAY_DESC) != 0u) {
        return &o->pValDesc[1];
    }
    return &o->pValDesc[sub];
}

static unsigned long size_of(const VALUE_DESC_T *d)
{
    switch (d->varType) {
    case CO_TYPEDESC_BOOL: case CO_TYPEDESC_UNSIGNED8: case CO_TYPEDESC_INTEGER8: return 1;
    case CO_TYPEDESC_UNSIGNED16: case CO_TYPEDESC_INTEGER16: return 2;
    case CO_TYPEDESC_UNSIGNED32: case CO_TYPEDESC_INTEGER32: case CO_TYPEDESC_REAL32: return 4;
    case CO_TYPEDESC_UNSIGNED64: case CO_TYPEDESC_INTEGER64: return 8;
    case CO_TYPEDESC_VISSTRING: case CO_TYPEDESC_OCTETSTRING:
        return ((const STRING_DATA_T *)(const void *)d->pDefaultVal)->maxLen;
    case CO_TYPEDESC_DOMAIN: return sizeof(UNSIGNED8 *);
    default: return 0;
    }
}

static void print_number(unsigned type, const UNSIGNED8 *p)
{
    UNSIGNED8 u8; UNSIGNED16 u16; UNSIGNED32 u32; UNSIGNED64 u64;
    INTEGER8 i8; INTEGER16 i16; INTEGER32 i32; INTEGER64 i64;
    switch (type) {
    case CO_TYPEDESC_BOOL: case CO_TYPEDESC_UNSIGNED8:
        memcpy(&u8, p, 1); printf("%u", (unsigned)u8); break;
    case CO_TYPEDESC_UNSIGNED16: memcpy(&u16, p, 2); printf("%u", (unsigned)u16); break;
    case CO_TYPEDESC_UNSIGNED32: memcpy(&u32, p, 4); printf("%lu", (unsigned long)u32); break;
    case CO_TYPEDESC_UNSIGNED64: memcpy(&u64, p, 8); printf("%llu", u64); break;
    case CO_TYPEDESC_INTEGER8: memcpy(&i8, p, 1); printf("%d", (int)i8); break;
    case CO_TYPEDESC_INTEGER16: memcpy(&i16, p, 2); printf("%d", (int)i16); break;
    case CO_TYPEDESC_INTEGER32: memcpy(&i32, p, 4); printf("%ld", (long)i32); break;
    case CO_TYPEDESC_INTEGER64: memcpy(&i64, p, 8); printf("%lld", i64); break;
    case CO_TYPEDESC_REAL32: memcpy(&u32, p, 4); printf("0x%08lX", (unsigned long)u32); break;
    default: printf("?"); break;
    }
}

static void print_hex(const UNSIGNED8 *p, unsigned long n)
{
    unsigned long i;
    if (n == 0u) {
        printf("-");
    }
    for (i = 0; i < n; i++) {
        printf("%02x", (unsigned)p[i]);
    }
}

int main(void)
{
    unsigned i, sub;
    unsigned count = CAT(OD_SYMBOL, Elements);
    for (i = 0; i < count; i++) {
        const LIST_ELEMENT_T *o = &OD_SYMBOL[i];
        unsigned long offset = 0;
        printf("%04X n=%u\n", (unsigned)o->index, (unsigned)o->numOfElem);
        for (sub = 0; sub < o->numOfElem; sub++) {
            const VALUE_DESC_T *d = desc_of(o, sub);
            const UNSIGNED8 *data = o->pObj + (o->numOfElem > 1u ? offset : 0u);
            unsigned type = d->varType;
            printf("%04X %02X t=%u a=%04X d=", (unsigned)o->index, sub, type,
                   (unsigned)(sub == 0u ? o->pValDesc[0].attribute : d->attribute));
            if (type == CO_TYPEDESC_VISSTRING || type == CO_TYPEDESC_OCTETSTRING) {
                const STRING_DATA_T *s = (const STRING_DATA_T *)(const void *)d->pDefaultVal;
                printf("len=%lu/%lu v=", (unsigned long)s->actLen, (unsigned long)s->maxLen);
                print_hex(data, s->actLen);
            } else if (type == CO_TYPEDESC_DOMAIN) {
                const DOMAIN_DATA_T *s = (const DOMAIN_DATA_T *)(const void *)d->pDefaultVal;
                const UNSIGNED8 *buf;
                memcpy(&buf, data, sizeof buf);
                printf("len=%lu v=", (unsigned long)s->len);
                print_hex(buf, s->len);
            } else {
                print_number(type, d->pDefaultVal);
                printf(" v=");
                print_number(type, data);
#if defined(CONFIG_LIMITS_CHECK) && defined(WALK_LIMITS)
                if (d->pLimits != NULL) {
                    const UNSIGNED8 *lim = (const UNSIGNED8 *)(const void *)d->pLimits;
                    printf(" l=");
                    print_number(type, lim);
                    printf("..");
                    print_number(type, lim + size_of(d));
                }
#endif
            }
            printf("\n");
            offset += size_of(d);
        }
    }
    return 0;
}
