"""Studies that run several campaigns and compare them with the thesis.

* ``cases`` -- the trend study's settings (:class:`TrendSettings`, full and ``--quick``) and the
  scenes it runs, written as TOML so that every case can be rerun alone with
  ``rubberfriction run``.
* ``evidence`` -- what the trend table reads from finished campaigns: plain numbers per case
  (:class:`Evidence`), stored as ``evidence.json``.
* ``trends`` -- the thesis' trend table (ch. 6.4, 6.5, 8.5.3): one :class:`Trend` per row, with
  the thesis' statement and the comparison it implies; :func:`build_rows` turns evidence into rows.
* ``run`` -- :func:`run_trends`: the campaigns, resumably and farmed over the ranks, then the table
  (``rubberfriction study trends``).
"""
