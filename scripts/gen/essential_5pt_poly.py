#!/usr/bin/env python3
"""Generates the polynomial products used by src/madsfm/solvers/essential_5pt.cc.

Prints two C++ functions (standard library only, no arguments):
  MulLinLin(a, b, out)   out (quadratic, 10 coeffs) = a (linear, 4) * b (linear, 4)
  MulQuadLinAdd(q, l, out)  out (cubic, 20 coeffs) += q (quadratic, 10) * l (linear, 4)
Monomial orders (exponents of x, y, z):
  linear    x y z 1
  quadratic x^2 xy xz y^2 yz z^2 x y z 1
  cubic     Nister 2004: x^3 y^3 x^2y xy^2 x^2z x^2 y^2z y^2 xyz xy | xz^2 xz x yz^2 yz y z^3 z^2 z 1
"""

LIN = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 0, 0)]
QUAD = [(2, 0, 0), (1, 1, 0), (1, 0, 1), (0, 2, 0), (0, 1, 1), (0, 0, 2),
        (1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 0, 0)]
CUBIC = [(3, 0, 0), (0, 3, 0), (2, 1, 0), (1, 2, 0), (2, 0, 1), (2, 0, 0), (0, 2, 1), (0, 2, 0), (1, 1, 1),
         (1, 1, 0), (1, 0, 2), (1, 0, 1), (1, 0, 0), (0, 1, 2), (0, 1, 1), (0, 1, 0), (0, 0, 3), (0, 0, 2),
         (0, 0, 1), (0, 0, 0)]


def add(e, f):
    return tuple(a + b for a, b in zip(e, f))


def product(name, ta, tb, tout, accumulate):
    terms = {i: [] for i in range(len(tout))}
    for i, e in enumerate(ta):
        for j, f in enumerate(tb):
            terms[tout.index(add(e, f))].append("a[%d] * b[%d]" % (i, j))
    lines = ["inline void %s(const double* a, const double* b, double* out) {" % name]
    for k in range(len(tout)):
        if terms[k]:
            op = "+=" if accumulate else "="
            lines.append("  out[%d] %s %s;" % (k, op, " + ".join(terms[k])))
        elif not accumulate:
            lines.append("  out[%d] = 0.0;" % k)
    lines.append("}")
    return "\n".join(lines)


if __name__ == "__main__":
    print(product("MulLinLin", LIN, LIN, QUAD, False))
    print()
    print(product("MulQuadLinAdd", QUAD, LIN, CUBIC, True))
