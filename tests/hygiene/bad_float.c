/* Negative fixture: must not compile under -mgeneral-regs-only. */
int hygiene_bad_float(int d);

int hygiene_bad_float(int d)
{
    return (int)(42000.0 / (double)d);
}
