// placeholder: filled in by the I/O and scenes work
