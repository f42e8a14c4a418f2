"""gearsim.io"""
