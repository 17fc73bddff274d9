"""``camcad bench``'s measurements, inside the package so that an installed camcad runs them.

``kernels`` (each kernel against its numpy floor and a fair peer), ``sweeps`` (designs per second per core),
``startup`` (whole processes against their import floors); ``floors``, ``peers`` and ``references`` hold the
second implementations and the independent references, none of which imports camcad.
"""
