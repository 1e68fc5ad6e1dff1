"""Published values the blood_capillary study sets its measurements beside: the in-vitro
apparent viscosity and Fahraeus effect of Pries, Neuhaus & Gaehtgens (Am J Physiol 263
(1992) H1770), and in-vivo cell-free layer widths (each with the sentence it was read from and
its address)."""
import math

# Published cell-free layer widths to set the measured one beside (um). Each was read in the
# source's abstract (the addresses below); the full papers were not at hand.
CELL_FREE_LAYER_PUBLISHED = {
    # Mean width of the cell-free layer, rat cremaster arterioles 20-40 um, systemic Ht 20 %
    # (hemodilution), high-speed video: "The CFL values were 5.4 +- 0.2, 3.1 +- 0.1 and
    # 0.9 +- 0.1 um at 20, 40 and 75% Hctsys". "Effect of systemic hematocrit on volume flow
    # and cell-free layer width in arterioles" (FASEB J abstract; authors not given on the page
    # read), https://discovery.researcher.life/article/effect-of-systemic-hematocrit-on-volume-
    # flow-and-cell-free-layer-width-in-arterioles/b163dae25b1233ec8ad82286b86555b8
    "invivo_arterioles_hct20": 5.4,
    # The red cells' exclusion zone (the gap to the cells nearest the wall, a lower bound on
    # the mean layer), rat arterioles 30-40 um: "decreased from 2.0 um at a systemic
    # hematocrit (Hct sys) of 20% to a value of 1.0 to 1.1 um over a wide Hct sys range of 30
    # to 60%". Yalcin O., Jivani M., Intaglietta M., Johnson P.C., FASEB J 24 (2010) 974.8,
    # doi 10.1096/fasebj.24.1_supplement.974.8.
    "exclusion_zone_yalcin2010_hct20": 2.0,
}


def cell_free_layer_comparison(width_um: float) -> dict:
    """The measured width minus each published one (CELL_FREE_LAYER_PUBLISHED), as metrics."""
    return {f"cell_free_layer_minus_{k}_um": width_um - v
            for k, v in CELL_FREE_LAYER_PUBLISHED.items()}


def pries_1992(tube_ht: float, d: float = 20.0) -> tuple[float, float]:  # d [um]
    """Relative apparent viscosity in vitro (Pries et al. 1992) at the discharge haematocrit
    whose tube haematocrit is `tube_ht`, and that discharge haematocrit."""
    f = 1 + 1.7 * math.exp(-0.35 * d) - 0.6 * math.exp(-0.01 * d)
    # H_T = H_D (H_D + (1 - H_D) f): a quadratic in H_D.
    a, b = 1 - f, f
    hd = (-b + math.sqrt(b * b + 4 * a * tube_ht)) / (2 * a)
    eta45 = 220 * math.exp(-1.3 * d) + 3.2 - 2.44 * math.exp(-0.06 * d ** 0.645)
    g = 1 / (1 + 1e-11 * d ** 12)
    c = (0.8 + math.exp(-0.075 * d)) * (-1 + g) + g
    return 1 + (eta45 - 1) * ((1 - hd) ** c - 1) / ((1 - 0.45) ** c - 1), hd
