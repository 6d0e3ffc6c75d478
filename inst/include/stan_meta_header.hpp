// Headers every Stan model of the package includes (none needed yet).
