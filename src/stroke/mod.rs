//! Strokes: the samples a pen produced, and the `kansei-stroke` v1 file format.
