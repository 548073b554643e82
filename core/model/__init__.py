"""The authored document: immutable records and reversible edits."""
