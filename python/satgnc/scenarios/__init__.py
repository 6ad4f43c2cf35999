"""The papers' set-ups as data, each value with its source."""
