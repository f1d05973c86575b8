/* Translation unit for the header self-containment checks. */
typedef int hygiene_empty_unit;
