/*
 * Minimal stand-in for the port CANopen Library's object-dictionary declarations, written
 * for dcf2bin's tests from the facts of seed 002 (LIST_ELEMENT_T, VALUE_DESC_T, the
 * CO_TYPEDESC_* variable types and the attribute bits). Numeric values of the codes and
 * bits, STRING_DATA_T and DOMAIN_DATA_T follow the library's public header. Only what
 * dcf2bin's generated source and the walker program need is here.
 */
#ifndef DCF2BIN_TEST_CO_ACCES_H
#define DCF2BIN_TEST_CO_ACCES_H

/* basic types: exact widths on the host */
typedef unsigned char      UNSIGNED8;
typedef unsigned short     UNSIGNED16;
typedef unsigned int       UNSIGNED32;
typedef unsigned long long UNSIGNED64;
typedef signed char        INTEGER8;
typedef signed short       INTEGER16;
typedef signed int         INTEGER32;
typedef signed long long   INTEGER64;
typedef float              REAL32;

/* limits of a value (only with CONFIG_LIMITS_CHECK): the lower, then the upper limit, in
 * the variable's own type (the manual names LIMIT_U8_T; pLimits points at the one of the
 * variable's type, cast) */
#define DCF2BIN_TEST_LIMIT(name, type) typedef struct { type minRange; type maxRange; } name;
DCF2BIN_TEST_LIMIT(LIMIT_U8_T, UNSIGNED8)
DCF2BIN_TEST_LIMIT(LIMIT_U16_T, UNSIGNED16)
DCF2BIN_TEST_LIMIT(LIMIT_U32_T, UNSIGNED32)
DCF2BIN_TEST_LIMIT(LIMIT_U64_T, UNSIGNED64)
DCF2BIN_TEST_LIMIT(LIMIT_I8_T, INTEGER8)
DCF2BIN_TEST_LIMIT(LIMIT_I16_T, INTEGER16)
DCF2BIN_TEST_LIMIT(LIMIT_I32_T, INTEGER32)
DCF2BIN_TEST_LIMIT(LIMIT_I64_T, INTEGER64)
DCF2BIN_TEST_LIMIT(LIMIT_R32_T, REAL32)

/* the manual's 64-bit initialisation, for a compiler with a 64-bit type */
#define SET_U64(b1, b2, b3, b4, b5, b6, b7, b8)        \
  { b1<<56|b2<<48|b3<<40|b4<<32|b5<<24|b6<<16|b7<<8|b8 };

/* size information behind pDefaultVal of strings and domains */
typedef struct {
    UNSIGNED32 actLen;   /* length in use */
    UNSIGNED32 maxLen;   /* room for the string */
} STRING_DATA_T;

typedef struct {
    UNSIGNED32 len;      /* domain length */
} DOMAIN_DATA_T;

/* description of one subindex */
typedef struct {
    UNSIGNED8 *pDefaultVal;      /* default value (typed data behind it) */
#ifdef CONFIG_LIMITS_CHECK
    LIMIT_U8_T *pLimits;         /* lower and upper limit */
#endif
    UNSIGNED8 varType;           /* CO_TYPEDESC_* */
    UNSIGNED16 attribute;        /* CO_*_PERM and friends */
} VALUE_DESC_T;

#ifdef CO_CONFIG_ENABLE_OBJ_CALLBACK
typedef int (*CO_OBJ_CB_T)(UNSIGNED16 index, UNSIGNED8 subIndex, void *arg);
#endif

/* one object dictionary index */
typedef struct {
    UNSIGNED8 *pObj;             /* the data */
    VALUE_DESC_T *pValDesc;      /* one description per subindex */
    UNSIGNED16 index;
    UNSIGNED8 numOfElem;         /* subindexes 0..numOfElem-1 */
#ifdef CO_CONFIG_ENABLE_OBJ_CALLBACK
    CO_OBJ_CB_T pObjCallback;
#endif
} LIST_ELEMENT_T;

/* variable types */
#define CO_TYPEDESC_BOOL         1u
#define CO_TYPEDESC_UNSIGNED8    2u
#define CO_TYPEDESC_UNSIGNED16   3u
#define CO_TYPEDESC_UNSIGNED32   5u
#define CO_TYPEDESC_UNSIGNED64   9u
#define CO_TYPEDESC_INTEGER8    10u
#define CO_TYPEDESC_INTEGER16   11u
#define CO_TYPEDESC_INTEGER32   12u
#define CO_TYPEDESC_INTEGER64   13u
#define CO_TYPEDESC_VISSTRING   14u
#define CO_TYPEDESC_OCTETSTRING 15u
#define CO_TYPEDESC_DOMAIN      16u
#define CO_TYPEDESC_REAL32      17u

/* attribute bits */
#define CO_UP_DN_LD_DOMAIN   ((UNSIGNED16)0x0001u)  /* domain: data is a pointer */
#define CO_SHORT_ARRAY_DESC  ((UNSIGNED16)0x0002u)  /* sub 1 describes subs 1..n */
#define CO_CONST_PERM        ((UNSIGNED16)0x0008u)  /* constant, may live in ROM */
#define CO_NUM_VAL           ((UNSIGNED16)0x0010u)  /* numeric (byte order matters) */
#define CO_READ_PERM         ((UNSIGNED16)0x0020u)  /* readable */
#define CO_WRITE_PERM        ((UNSIGNED16)0x0040u)  /* writable */
#define CO_MAP_PERM          ((UNSIGNED16)0x0080u)  /* PDO mappable */
#define CO_OBJ_ATTR_SAVE     ((UNSIGNED16)0x1000u)  /* keep in non-volatile memory */

#endif
