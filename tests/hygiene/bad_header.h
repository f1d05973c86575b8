/* Negative fixture: uses a type without including its header. */
#ifndef HYGIENE_BAD_HEADER_H
#define HYGIENE_BAD_HEADER_H
typedef struct bad {
    uint8_t *data;
} bad_t;
#endif
