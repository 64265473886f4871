//! Linux evdev recordings in the evemu format (in progress).
