"""The 21 error factors of Sun et al. 2014, Table 1: the catalog (``catalog``), their transfer
formulas (``transfers``), Eq. (1) (``output``) and the readings of a tolerance zone
(``distributions``)."""
