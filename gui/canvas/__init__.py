"""The drawing canvas: view, items, and tools consuming a small canvas-event type."""
