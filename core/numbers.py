"""Numbers as a reader sees them: a value rounded to what its ± supports, plain numbers and vectors.

Every console table, sentence and report page of massline prints its numbers through this module, so
that no value shows more digits than its uncertainty supports ("4.00127 ± 0.035" becomes
"4.001 ± 0.035"), no "−0" is ever printed and no numpy repr ("[-1.  0.  0.]") reaches a reader.
Minus signs are the true minus sign "−" (U+2212). JSON files keep full precision: they never pass here.

Values between 10⁻³ and 10⁶ are written plainly; smaller or larger ones in scientific notation, a
value and its σ then sharing one exponent ("4.254e−5 ± 0.030e−5").
"""

from __future__ import annotations

import math
import re
from decimal import ROUND_DOWN, ROUND_HALF_EVEN, Context, Decimal

MINUS = "−"
SMALLEST_PLAIN, LARGEST_PLAIN = -3, 5  # decimal exponents of the leading digit written without an exponent
RESOLUTION = 1e-9  # a value below this fraction of its quantity's scale is rounding noise: written 0
EXACT = Context(prec=1000)  # room for any double's digits from its leading one to a σ's last (|exponents| ≤ 324)


def _decimal(value: float) -> Decimal:
    """The float as the decimal its shortest repr names (what a reader would type)."""
    return Decimal(repr(float(value)))


def _rounded(d: Decimal, place: int) -> Decimal:
    """``d`` rounded to the digit of 10**place, with no negative zero."""
    r = d.quantize(Decimal((0, (1,), place)), rounding=ROUND_HALF_EVEN, context=EXACT)
    return r.copy_abs() if r.is_zero() else r


def _leading(d: Decimal) -> int:
    """Decimal exponent of the leading digit (0 for zero)."""
    return 0 if d.is_zero() else d.adjusted()


def _fixed(d: Decimal, place: int) -> str:
    return format(_rounded(d, place), "f").replace("-", MINUS)


def _scientific(d: Decimal, place: int, exponent: int) -> str:
    mantissa = _fixed(d.scaleb(-exponent, context=EXACT), place - exponent)
    return f"{mantissa}e{exponent}".replace("-", MINUS)


def _written(d: Decimal, place: int, exponent: int) -> str:
    """``d`` to the digit of 10**place, plainly when ``exponent`` (the leading digit's) allows, else with it."""
    if SMALLEST_PLAIN <= exponent <= LARGEST_PLAIN:
        return _fixed(d, place)
    return _scientific(d, place, exponent)


def sigma_place(sigma: float) -> int:
    """Decimal place of the last digit a 1-σ keeps, by the Particle Data Group's rule.

    Take σ's three leading digits (truncated): 100–354 keep two significant digits, 355–949 one, and 950–999 are
    raised to 1000 and keep two ("0.0996" → "0.10"). Particle Data Group, *Review of Particle Physics*,
    Introduction, "Rounding" (R. L. Workman et al., Prog. Theor. Exp. Phys. 2022, 083C01).
    """
    d = _decimal(sigma)
    three = int(d.scaleb(2 - d.adjusted()).to_integral_value(ROUND_DOWN))
    return d.adjusted() - 1 if three <= 354 else d.adjusted()


def value_with_sigma(value: float, sigma: float | None) -> tuple[str, str]:
    """A value and its 1-σ as two texts, the value rounded to the σ's last digit (:func:`sigma_place`).

    σ None: the value alone (:func:`number`), σ text "". NaN value or σ: ("unobservable", "").
    σ = 0: the value by :func:`number`, σ "0"; σ = ∞: σ "∞". Both texts share one exponent when the
    numbers are too small or too large to write plainly.
    """
    if sigma is None:
        return number(value), ""
    if math.isnan(value) or math.isnan(sigma):
        return "unobservable", ""
    if math.isinf(value) or math.isinf(sigma) or sigma == 0:
        return number(value), sigma_text(sigma)
    place = sigma_place(abs(sigma))
    v, s = _rounded(_decimal(value), place), _rounded(_decimal(abs(sigma)), place)
    exponent = _leading(s) if v.is_zero() else max(_leading(v), _leading(s))
    return _written(v, place, exponent), _written(s, place, exponent)


def sigma_text(sigma: float) -> str:
    """A 1-σ alone, to the digits :func:`sigma_place` keeps ("—" for NaN, "∞", "0")."""
    if math.isnan(sigma):
        return "—"
    if math.isinf(sigma):
        return "∞"
    if sigma == 0:
        return "0"
    place = sigma_place(abs(sigma))
    s = _rounded(_decimal(abs(sigma)), place)
    return _written(s, place, _leading(s))


def number(value: float, digits: int = 6, scale: float | None = None) -> str:
    """A value with at most ``digits`` significant digits, trailing zeros dropped ("—" for NaN); 0 when it is
    below ``RESOLUTION`` of its quantity's ``scale`` (a CoG of 1e−16 m on a 0.1 m body is the arithmetic's)."""
    if scale is not None and abs(value) < RESOLUTION * abs(scale):
        value = 0.0
    if math.isnan(value):
        return "—"
    if math.isinf(value):
        return "∞" if value > 0 else MINUS + "∞"
    d = _decimal(value)
    r = _rounded(d, _leading(d) - digits + 1)
    return _trimmed(r)


def _trimmed(d: Decimal) -> str:
    """``d`` written without trailing zeros, plainly or with its leading digit's exponent."""
    exponent, place = _leading(d), d.normalize(context=EXACT).as_tuple().exponent
    if SMALLEST_PLAIN <= exponent <= LARGEST_PLAIN:
        place = min(place, 0)
    return _written(d, place, exponent)


def formatted(value: float, spec: str) -> str:
    """``format(value, spec)`` with the true minus sign, no "−0" and a short exponent ("1.5e3"); "—" for NaN."""
    if math.isnan(value) or math.isinf(value):
        return number(value)
    text = re.sub(r"e\+?(-?)0*(\d)", r"e\1\2", format(value, spec))  # "1.5e+03" → "1.5e3", "e-05" → "e-5"
    if text.startswith("-") and not any(c in "123456789" for c in text.split("e")[0]):
        text = ("+" if "+" in spec else "") + text[1:]
    return text.replace("-", MINUS)


def signed(text: str) -> str:
    """A printed number with an explicit "+" when it is positive (zero and negative ones as they are)."""
    if text.startswith(MINUS) or not any(c in "123456789" for c in text.partition("e")[0]):
        return text
    return "+" + text


def vector_text(vector, digits: int = 4) -> str:
    """A point or a direction as "(x, y, z)": every entry to the place of the largest one's ``digits``-th
    significant digit, trailing zeros dropped ("(0, 0, −1)", "(0.16, 0.06, 0.006)")."""
    entries = [_decimal(x) for x in vector]
    if any(not x.is_finite() for x in entries):
        return "(" + ", ".join(number(float(x), digits) for x in entries) + ")"
    exponent = max((_leading(x) for x in entries if not x.is_zero()), default=0)
    rounded = [_rounded(x, exponent - digits + 1) for x in entries]
    return "(" + ", ".join(_trimmed(x) for x in rounded) + ")"


def counted(n: int, noun: str, plural: str | None = None) -> str:
    """"1 hit", "3 hits": a count with its noun in the number it takes (``plural`` where it is not noun + s)."""
    return f"{n} {noun if n == 1 else plural or noun + 's'}"
