"""Synthesis: a mechanism from what the designer needs, returned as an ordinary scene element.

What goes here: linkage path, motion and function synthesis (an atlas of coupler-curve and
input-output descriptors built with ``studies``, nearest-neighbour retrieval, alignment and
least-squares refinement; Burmester and Freudenstein where exact), Geneva drives sized from
requirements (speed, load, contact stress, wear life, size limits), rolling levers with a
prescribed slider law, and non-circular gear pitch curves from a transmission function. Every
result validates, can be driven and exports cut-ready parts. Layer: above ``studies`` (it searches
with the batch engine), below ``io``, ``workspace`` and ``cli``.
"""
