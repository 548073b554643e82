"""Kinetostatics of linkages, solved group by group in closed form along the Assur decomposition.

:mod:`.kinetostatics` is the entry point (:func:`~.kinetostatics.linkage_forces`, the result
record and its conventions), :mod:`.static` prepares each link's applied loads, :mod:`.passes`
runs the pass from the last group back to the driver, and :mod:`.report` makes the summary text
and the CSV table.
"""
