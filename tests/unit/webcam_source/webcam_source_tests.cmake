# webcam_source tests (filled in by the work on this area).
