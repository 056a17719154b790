# webcam tests (filled in by the work on this area).
