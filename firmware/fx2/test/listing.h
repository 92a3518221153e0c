/* listing.h — the firmware image as sdcc's relocated listings (*.rst, one
 * per module, written by the link) and its .ihx describe it: the address of
 * every label (static functions and tables too, which the .map leaves out)
 * and where every instruction starts.  Code the listings do not cover (the
 * startup and library routines sdcc links in) is decoded linearly from the
 * image, which holds no data between those routines' instructions.  Host
 * code for the firmware tests and the speed figures. */
#ifndef ALBATROS_LISTING_H
#define ALBATROS_LISTING_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define LISTING_CODE 0x10000u

typedef struct {
    char name[48];
    unsigned addr;
    bool code;                /* a label in front of an instruction */
} listing_label;

typedef struct {
    uint8_t rom[LISTING_CODE];     /* the image */
    bool loaded[LISTING_CODE];     /* bytes the image defines */
    bool insn[LISTING_CODE];       /* an instruction starts here */
    uint8_t listed[LISTING_CODE];  /* sdas's cycle column (12-clock cycles), 0: decoded here */
    listing_label *labels;         /* sorted by address */
    size_t nlabels;
    unsigned code_end;             /* one past the last code byte (the CONST area follows) */
    char error[512];
} listing_t;

/* The image ihx and the *.rst files in dir. 0, or -1 with l->error. */
int listing_load(listing_t *l, const char *ihx, const char *dir);
void listing_free(listing_t *l);

/* The address of a label, or -1. */
long listing_addr(const listing_t *l, const char *name);
/* The code label at or below addr (the function it is in), or NULL. */
const listing_label *listing_function(const listing_t *l, unsigned addr);

#endif
