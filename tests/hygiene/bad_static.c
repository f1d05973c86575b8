/* Negative fixture: both analysers must report these bugs. */
#include <string.h>

int hygiene_bad_static(int *p, int n);

int hygiene_bad_static(int *p, int n)
{
    int a[4];
    memset(a, 0, sizeof(p));
    if (n > 3) {
        p = 0;
    }
    return a[4] + *p;
}
