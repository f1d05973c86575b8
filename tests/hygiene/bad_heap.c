/* Negative fixture: the symbol check must reject this object. */
#include <stdio.h>
#include <stdlib.h>

int hygiene_bad_heap(int n);

int hygiene_bad_heap(int n)
{
    char *p = malloc((size_t)n);
    if (p == NULL) {
        return -1;
    }
    printf("%p\n", (void *)p);
    free(p);
    return 0;
}
