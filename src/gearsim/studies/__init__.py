"""gearsim.studies"""
