"""Adhesive friction from measurements (thesis ch. 7): measurement files, the real contact area
of a campaign, and the least-squares fit of the bell law (eqs. 7.3-7.8).

* :mod:`.measurements` -- friction measurement files (v, mu with stated units), one per surface
  condition (dry, water, soap-water), and the (v, mu_H) / (v, A_r) curve files of the same format;
* :mod:`.area` -- A_r(v) and mu_H(v) of a finished campaign folder (eq. 7.4, 7.5);
* :mod:`.fit` -- mu_diff(v) by the original (7.3, 7.4) and modified (7.5) approach, the fit of
  tau0, c, v0 in mu_A = tau_A A_r / p (7.6, 7.7) with standard errors, the share alpha (7.8);
* :mod:`.plots` -- fig. 7.6 (A_r over v; mu_diff and the fitted mu_A over v).

The bell law itself is :class:`rubberfriction.driver.theory.adhesion.BellLaw`, the project's one
bell-law type.
"""
