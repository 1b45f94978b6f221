"""Selective assembly (issue 39; docs/selective-assembly.md): pins and crank needle rollers taken per
unit from diameter classes, the yield it buys, the parts it leaves over, and the assembly sheet of a
measured batch. Rooms: ``classes`` (class sets, the selection's settings, the part laws' tables),
``rules`` (the compiled rules), ``source`` (the selected production run), ``run`` (random vs
selected), ``inventory`` (finite batches: the assignment), ``assembly`` (the assembly sheet)."""
